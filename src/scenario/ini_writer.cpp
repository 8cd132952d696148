// The resolved scenario text written into every result file: each key with its final value.
#include <optional>
#include <sstream>

#include "fretbem/core/format.hpp"
#include "fretbem/scenario/key_table.hpp"
#include "keys.hpp"
#include "sections.hpp"

namespace fretbem::scenario_detail {

namespace {

// ---- resolved text: every key with its final value; unset optional keys as comments ----

class IniWriter {
 public:
  void section(const std::string& name) {
    out_ << (out_.tellp() > 0 ? "\n[" : "[") << name << "]\n";
  }
  void put(const std::string& key, const std::string& value) {
    out_ << key << " = " << value << "\n";
  }
  void put(const std::string& key, double v) { put(key, format_number(v)); }
  void put(const std::string& key, int v) { put(key, std::to_string(v)); }
  void put(const std::string& key, bool v) { put(key, std::string(v ? "true" : "false")); }
  void put(const std::string& key, const std::optional<double>& v) {
    if (v)
      put(key, *v);
    else
      out_ << "# " << key << " = (unset)\n";
  }
  void put(const std::string& key, const fs::path& p) {
    if (p.empty())
      out_ << "# " << key << " = (unset)\n";
    else
      put(key, p.string());
  }
  /// A choice key's value, spelled as the key table spells choice `index` of "section.key".
  template <class Enum>
  void put_choice(const std::string& key, Enum index) {
    put(std::string(short_name(key)), choice_name(key, static_cast<std::size_t>(index)));
  }
  void raw(const std::string& line) { out_ << line << "\n"; }
  std::string str() const { return out_.str(); }

 private:
  std::ostringstream out_;
};

void write_material(IniWriter& w, const Material& m) {
  w.section("material");
  w.put("E", m.body1.E);
  w.put("nu", m.body1.nu);
  w.put("E2", m.body2 ? std::optional<double>(m.body2->E) : std::nullopt);
  w.put("nu2", m.body2 ? std::optional<double>(m.body2->nu) : std::nullopt);
  w.put("mu", m.mu);
}

void write_grid(IniWriter& w, const Grid& g, bool allow_edge_contact) {
  w.section("grid");
  if (g.nx == g.ny) {
    w.put("n", g.nx);
  } else {
    w.put("nx", g.nx);
    w.put("ny", g.ny);
  }
  w.put("length", g.length_x());
  w.put("periodic", g.periodic);
  w.put("allow_edge_contact", allow_edge_contact);
}

void write_surface(IniWriter& w, const SurfaceSpec& s) {
  w.section("surface");
  w.put_choice("surface.type", s.type);
  w.put("radius", s.radius > 0 ? std::optional<double>(s.radius) : std::nullopt);
  w.put("hurst", s.rough.hurst);
  w.put("rms_height", s.rough.rms_height);
  w.put("rms_slope", s.rough.rms_slope);
  w.put_choice("surface.method", s.rough.method);
  w.put("seed", std::to_string(s.rough.seed));
  w.put("rolloff_wavelength", s.rough.rolloff_wavelength);
  w.put("cutoff_wavelength", s.rough.cutoff_wavelength);
  w.put("file", s.file);
  if (s.dataset.empty())
    w.raw("# dataset = (unset)");
  else
    w.put("dataset", s.dataset);
  w.put_choice("surface.layout", s.layout);
  w.put("spacing", s.spacing);
}

void write_load(IniWriter& w, const LoadSpec& l) {
  w.section("load");
  w.put("normal_force", l.normal_force);
  w.put("indentation", l.indentation);
  w.put_choice("load.path", l.path);
  w.put_choice("load.control", l.control);
  w.put("amplitude", l.amplitude);
  w.put("displacement_amplitude", l.displacement_amplitude);
  w.put("direction", l.direction);
  w.put("cycles", l.cycles);
  w.put("steps_per_cycle", l.steps_per_cycle);
  w.put("steps", l.steps);
  w.put("table", l.table);
  w.put("allow_large_shift", l.allow_large_shift);
  w.put("tolerance", l.tolerance);
  w.put("substeps", l.substeps);
  w.put_choice("load.interpolation", l.interpolation);
}

void write_solver(IniWriter& w, const SolverSpec& s) {
  w.section("solver");
  w.put("tolerance", s.tolerance);
  w.put("max_iterations", s.max_iterations);
  w.put_choice("solver.coupling", s.coupling);
  // Only coupled runs name these: resolved texts (and checkpoints) of other runs carry no keys
  // they do not use.
  if (s.coupling == Coupling::coupled) {
    w.put("coupling_tolerance", s.coupling_tolerance);
    w.put("coupling_iterations", s.coupling_iterations);
  }
  w.put("threads", s.threads);
  w.put_choice("solver.algorithm", s.algorithm);
  w.put_choice("solver.stiffness", s.stiffness);
  w.put_choice("solver.fft_plan", s.fft_plan);
  w.put_choice("solver.fft_precision", s.fft_precision);
  w.put_choice("solver.monotone", s.monotone);
  // Written only when not the default (auto): resolved scenarios of default runs carry no
  // predictor key (and a checkpoint written without the key resumes with auto).
  if (s.predictor != PredictorMode::automatic) w.put_choice("solver.predictor", s.predictor);
  // The table spells the choices automatic|on|off, not in Precondition's order.
  w.put("precondition", std::string(s.precondition == Precondition::automatic ? "automatic"
                                    : s.precondition == Precondition::on      ? "on"
                                                                              : "off"));
}

void write_output(IniWriter& w, const OutputSpec& o) {
  w.section("output");
  w.put("dir", o.dir.string());
  std::string fields;
  for (const auto& f : o.fields) fields += (fields.empty() ? "" : ", ") + f;
  w.put("fields", fields.empty() ? std::string("none") : fields);
  w.put("fields_every", o.fields_every);
  w.put("checkpoint_every", o.checkpoint_every);
}

void write_wear(IniWriter& w, const WearSpec& s) {
  w.section("wear");
  w.put_choice("wear.law", s.law);
  // 0 means "not given" (both must be > 0 when given).
  w.put("coefficient", s.coefficient > 0 ? std::optional<double>(s.coefficient) : std::nullopt);
  w.put("cycles", s.cycles > 0 ? std::optional<double>(s.cycles) : std::nullopt);
  w.put_choice("wear.integrator", s.integrator);
  w.put("rtol", s.rtol);
  w.put("atol", s.atol > 0 ? std::optional<double>(s.atol) : std::nullopt);  // 0: not given
  w.put_choice("wear.newton", s.newton);
  w.put("indenter_share", s.indenter_share);
}

void write_friction(IniWriter& w, const FrictionSpec& f) {
  w.section("friction");
  w.put_choice("friction.law", f.law);
  w.put("mu_kinetic", f.mu_kinetic > 0 ? std::optional<double>(f.mu_kinetic) : std::nullopt);
  w.put("mu_final", f.mu_final > 0 ? std::optional<double>(f.mu_final) : std::nullopt);
  w.put_choice("friction.evolution", f.evolution);
  w.put("scale", f.scale > 0 ? std::optional<double>(f.scale) : std::nullopt);
}

}  // namespace

std::string resolved_text(const Scenario& s) {
  IniWriter w;
  w.raw("# fretbem " FRETBEM_VERSION " resolved scenario '" + s.name + "'");
  w.raw("# relative paths below were resolved against the scenario's folder");
  write_material(w, s.material);
  write_grid(w, s.grid, s.allow_edge_contact);
  write_surface(w, s.surface);
  write_load(w, s.load);
  write_solver(w, s.solver);
  write_output(w, s.output);
  write_wear(w, s.wear);
  write_friction(w, s.friction);
  return w.str();
}

}  // namespace fretbem::scenario_detail
