// The table of conditional keys: each key with the condition under which the run reads it.
#include "fretbem/scenario/ignored_keys.hpp"

#include <algorithm>
#include <functional>

#include "fretbem/scenario/key_table.hpp"

namespace fretbem {

namespace {

const char* path_name(PathType p) {
  return choice_name("load.path", static_cast<std::size_t>(p)).c_str();
}

const char* surface_name(SurfaceType t) {
  return choice_name("surface.type", static_cast<std::size_t>(t)).c_str();
}

const char* integrator_name(WearIntegrator i) {
  return choice_name("wear.integrator", static_cast<std::size_t>(i)).c_str();
}

const char* friction_name(FrictionLawKind k) {
  return choice_name("friction.law", static_cast<std::size_t>(k)).c_str();
}

bool scripted(const Scenario& sc) {
  return sc.load.path == PathType::ramp || sc.load.path == PathType::sine;
}

bool wear_run(const Scenario& sc) {
  return sc.wear.law != WearLaw::none;
}

std::string here(const std::string& what) {
  return " (here " + what + ")";
}

// A rule answers "" when the key is read, else when it would be read and what the scenario
// has instead.
using Unread = std::function<std::string(const Scenario&)>;

Unread unless_surface(SurfaceType t) {
  return [t](const Scenario& sc) -> std::string {
    if (sc.surface.type == t) return "";
    return std::string("read only with surface.type = ") + surface_name(t) +
           here(surface_name(sc.surface.type));
  };
}

Unread unless_path(PathType p) {
  return [p](const Scenario& sc) -> std::string {
    if (sc.load.path == p) return "";
    return std::string("read only with load.path = ") + path_name(p) +
           here(path_name(sc.load.path));
  };
}

Unread unless_control(Control c) {
  return [c](const Scenario& sc) -> std::string {
    if (scripted(sc) && sc.load.control == c) return "";
    const std::string want = std::string("read only by a ramp or sine with load.control = ") +
                             (c == Control::force ? "force" : "displacement");
    if (!scripted(sc)) return want + here(std::string("load.path = ") + path_name(sc.load.path));
    return want + here(sc.load.control == Control::force ? "force" : "displacement");
  };
}

Unread unless_wear() {
  return [](const Scenario& sc) -> std::string {
    return wear_run(sc) ? "" : "read only in a wear run (here wear.law = none)";
  };
}

// ARKODE's keys: the integrators erk, dirk and arkode; cycle simulates every cycle instead.
Unread unless_ode_integrator() {
  return [](const Scenario& sc) -> std::string {
    if (!wear_run(sc)) return unless_wear()(sc);
    if (sc.wear.integrator != WearIntegrator::cycle) return "";
    return "read only by the ARKODE wear integrators erk, dirk, arkode (here cycle)";
  };
}

Unread unless_friction(FrictionLawKind k) {
  return [k](const Scenario& sc) -> std::string {
    if (sc.friction.law == k) return "";
    return std::string("read only with friction.law = ") + friction_name(k) +
           here(friction_name(sc.friction.law));
  };
}

struct Rule {
  const char* key;
  Unread unread;
};

// Over 80 lines on purpose: one entry per key a choice can leave unread and nothing else, so
// its length is the number of such keys; a single list is where a new key's rule is looked for.
const std::vector<Rule>& rules() {
  static const std::vector<Rule> table = {
      {"grid.allow_edge_contact",
       [](const Scenario& sc) -> std::string {
         if (sc.surface.type != SurfaceType::sphere)
           return "only a sphere is refused for edge contact" +
                  here(std::string("surface.type = ") + surface_name(sc.surface.type));
         return sc.grid.periodic ? "a periodic grid has no edge (grid.periodic = true)" : "";
       }},
      {"surface.radius", unless_surface(SurfaceType::sphere)},
      {"surface.hurst", unless_surface(SurfaceType::rough)},
      {"surface.rms_height", unless_surface(SurfaceType::rough)},
      {"surface.rms_slope", unless_surface(SurfaceType::rough)},
      {"surface.method", unless_surface(SurfaceType::rough)},
      {"surface.seed", unless_surface(SurfaceType::rough)},
      {"surface.rolloff_wavelength", unless_surface(SurfaceType::rough)},
      {"surface.cutoff_wavelength", unless_surface(SurfaceType::rough)},
      {"surface.file", unless_surface(SurfaceType::file)},
      {"surface.dataset",
       [](const Scenario& sc) -> std::string {
         if (sc.surface.type != SurfaceType::file) return unless_surface(SurfaceType::file)(sc);
         std::string ext = sc.surface.file.extension().string();
         std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
         if (ext == ".h5" || ext == ".hdf5" || ext == ".npz") return "";
         return "read only from .h5, .hdf5 and .npz height maps" +
                here(ext.empty() ? "a text file" : ext);
       }},
      {"surface.layout",
       [](const Scenario& sc) -> std::string {
         if (sc.surface.type != SurfaceType::file) return unless_surface(SurfaceType::file)(sc);
         std::string ext = sc.surface.file.extension().string();
         std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
         return ext == ".x3p" ? "an x3p file carries its own axis order" : "";
       }},
      {"surface.spacing", unless_surface(SurfaceType::file)},
      // A table's Ux/Uy columns need load.control = displacement, its Fx/Fy force.
      {"load.control",
       [](const Scenario& sc) -> std::string {
         if (sc.load.path != PathType::none) return "";
         return "read only by a ramp, sine or table (here load.path = none)";
       }},
      {"load.amplitude", unless_control(Control::force)},
      {"load.displacement_amplitude", unless_control(Control::displacement)},
      {"load.allow_large_shift",
       [](const Scenario& sc) -> std::string {
         if (sc.load.path == PathType::table ||
             (scripted(sc) && sc.load.control == Control::displacement))
           return "";
         return "read only by displacement-controlled ramps and sines and by tables" +
                here(std::string("load.path = ") + path_name(sc.load.path));
       }},
      {"load.direction",
       [](const Scenario& sc) -> std::string {
         if (scripted(sc)) return "";
         return std::string("read only by a ramp or sine") +
                (sc.load.path == PathType::table ? " (a table's columns give the direction)"
                                                 : here("load.path = none"));
       }},
      {"load.cycles",
       [](const Scenario& sc) -> std::string {
         if (sc.load.path != PathType::sine) return unless_path(PathType::sine)(sc);
         return wear_run(sc) ? "wear runs simulate cycles up to wear.cycles" : "";
       }},
      {"load.steps_per_cycle", unless_path(PathType::sine)},
      {"load.steps", unless_path(PathType::ramp)},
      {"load.table", unless_path(PathType::table)},
      {"load.substeps",
       [](const Scenario& sc) -> std::string {
         if (sc.load.path != PathType::table) return unless_path(PathType::table)(sc);
         if (sc.load.tolerance > 0.0)
           return "read only without load.tolerance (the step control sets the sub-steps)";
         return wear_run(sc) ? "wear runs solve a table's rows whole" : "";
       }},
      {"load.interpolation",
       [](const Scenario& sc) -> std::string {
         if (sc.load.path != PathType::table) return unless_path(PathType::table)(sc);
         return wear_run(sc) ? "wear runs solve a table's rows and book the trapezoid between "
                               "them (docs/algorithms.md)"
                             : "";
       }},
      {"solver.coupling_tolerance",
       [](const Scenario& sc) -> std::string {
         return sc.solver.coupling == Coupling::coupled
                    ? ""
                    : "read only with solver.coupling = coupled";
       }},
      {"solver.coupling_iterations",
       [](const Scenario& sc) -> std::string {
         return sc.solver.coupling == Coupling::coupled
                    ? ""
                    : "read only with solver.coupling = coupled";
       }},
      {"output.fields_every",
       [](const Scenario& sc) -> std::string {
         return sc.output.fields.empty() ? "no output.fields are saved" : "";
       }},
      {"output.checkpoint_every",
       [](const Scenario& sc) -> std::string {
         return wear_run(sc) ? "a wear run checkpoints after every wear step" : "";
       }},
      {"wear.coefficient", unless_wear()},
      {"wear.cycles", unless_wear()},
      {"wear.integrator", unless_wear()},
      {"wear.rtol", unless_ode_integrator()},
      {"wear.atol", unless_ode_integrator()},
      {"wear.newton",
       [](const Scenario& sc) -> std::string {
         if (!wear_run(sc)) return unless_wear()(sc);
         const WearIntegrator i = sc.wear.integrator;
         if (i == WearIntegrator::dirk || i == WearIntegrator::arkode) return "";
         return std::string("read only by the implicit wear integrators dirk and arkode") +
                here(integrator_name(i));
       }},
      {"wear.indenter_share", unless_wear()},
      {"friction.mu_kinetic", unless_friction(FrictionLawKind::static_kinetic)},
      {"friction.mu_final", unless_friction(FrictionLawKind::evolving)},
      {"friction.evolution", unless_friction(FrictionLawKind::evolving)},
      {"friction.scale", unless_friction(FrictionLawKind::evolving)},
  };
  return table;
}

bool given(const Scenario& sc, const std::string& key) {
  return std::binary_search(sc.given_keys.begin(), sc.given_keys.end(), key);
}

}  // namespace

std::vector<IgnoredKey> ignored_keys(const Scenario& sc) {
  std::vector<IgnoredKey> out;
  for (const Rule& rule : rules()) {
    if (!given(sc, rule.key)) continue;
    if (std::string why = rule.unread(sc); !why.empty()) out.push_back({rule.key, why});
  }
  return out;
}

std::vector<std::string> ignored_key_warnings(const Scenario& sc) {
  std::vector<std::string> out;
  for (const auto& [key, why] : ignored_keys(sc)) out.push_back(key + " is ignored: " + why);
  return out;
}

std::vector<std::string> conditional_keys() {
  std::vector<std::string> out;
  for (const Rule& rule : rules()) out.push_back(rule.key);
  return out;
}

}  // namespace fretbem
