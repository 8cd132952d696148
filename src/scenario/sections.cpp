// Section readers: convert and check every value, then the rules that tie keys together.
#include "sections.hpp"

#include <algorithm>
#include <boost/program_options.hpp>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "fretbem/core/csv_reader.hpp"
#include "fretbem/core/errors.hpp"
#include "fretbem/core/format.hpp"
#include "fretbem/scenario/key_table.hpp"
#include "keys.hpp"

namespace fretbem::scenario_detail {

namespace po = boost::program_options;

namespace {

// nx*ny and the 2nx x 2ny padded FFT grid stay inside a 32-bit int index.
constexpr long long kMaxNodes = 1LL << 28;

}  // namespace

void read_file_entries(const std::string& text, Reader& r) {
  po::options_description desc;
  for (const auto& k : scenario_keys())
    desc.add_options()(std::string(k.key).c_str(), po::value<std::string>());
  std::istringstream in(text);
  po::parsed_options parsed(&desc);
  try {
    parsed = po::parse_config_file(in, desc, /*allow_unregistered=*/true);
  } catch (const std::exception& e) {
    r.fail(printable(e.what()));
  }
  std::set<std::string> seen;
  for (const auto& opt : parsed.options) {
    const std::string key = normalise_key(opt.string_key);
    const std::string value = opt.value.empty() ? std::string() : trim(opt.value.front());
    if (short_name(key).empty())
      r.fail("a line has no key before '=' (value '" + printable(value) + "')");
    reject_unknown(key, r.file());
    if (!seen.insert(key).second)
      r.fail("duplicated key '" + key + "' (" + printable(r.raw(key)) + " and " + printable(value) +
             ")");
    r.set(key, Entry{value, ""});
  }
}

void apply_override(const std::string& text, Reader& r) {
  const std::string where = "--set " + printable(text);
  const auto eq = text.find('=');
  if (eq == std::string::npos) throw InputError(where + ": expected section.key=value");
  const std::string key = normalise_key(text.substr(0, eq));
  if (short_name(key).empty()) throw InputError(where + ": expected section.key=value");
  reject_unknown(key, where);
  r.set(key, Entry{trim(text.substr(eq + 1)), where});
}

void read_material(const Reader& r, Material& m) {
  r.require("material.E");
  r.require("material.nu");
  m.body1 = Body{r.number("material.E"), r.number("material.nu")};
  if (r.has("material.E2") != r.has("material.nu2"))
    r.fail("material.E2 and material.nu2 describe the second body: give both or neither");
  if (r.has("material.E2")) m.body2 = Body{r.number("material.E2"), r.number("material.nu2")};
  if (r.has("material.mu")) m.mu = r.number("material.mu");
}

void read_grid(const Reader& r, Grid& g) {
  const bool both = r.has("grid.nx") && r.has("grid.ny");
  if (!both) r.require("grid.n", " (or both grid.nx and grid.ny)");
  const long long n = r.has("grid.n") ? r.count("grid.n") : 0;
  const long long nx = r.has("grid.nx") ? r.count("grid.nx") : n;
  const long long ny = r.has("grid.ny") ? r.count("grid.ny") : n;
  // grid.nx and grid.ny together define the grid (an override of a file's grid.n); one of them
  // beside a different grid.n is ambiguous (n = 32, nx = 16: 16 x 32 or 16 x 16?).
  if (r.has("grid.n") && !both)
    for (const auto& [key, side] : {std::pair{"grid.nx", nx}, std::pair{"grid.ny", ny}})
      if (r.has(key) && side != n)
        r.fail(std::string(key) + " = " + std::to_string(side) + " conflicts with grid.n = " +
               std::to_string(n) + ": give grid.n alone, or both grid.nx and grid.ny");
  if (nx * ny > kMaxNodes)
    r.fail("grid of " + std::to_string(nx) + " x " + std::to_string(ny) +
           " nodes is too large (at most 2^28 nodes)");
  r.require("grid.length");
  const double length = r.number("grid.length");
  g = Grid{static_cast<int>(nx), static_cast<int>(ny), length / static_cast<double>(nx),
           r.has("grid.periodic") && r.boolean("grid.periodic")};
}

void read_rough(const Reader& r, RoughSpec& s) {
  if (r.has("surface.hurst")) s.hurst = r.number("surface.hurst");
  if (r.has("surface.rms_height")) s.rms_height = r.number("surface.rms_height");
  if (r.has("surface.rms_slope")) s.rms_slope = r.number("surface.rms_slope");
  if (r.has("surface.method")) s.method = static_cast<RoughMethod>(r.option("surface.method"));
  if (r.has("surface.seed")) s.seed = r.unsigned64("surface.seed");
  if (r.has("surface.rolloff_wavelength"))
    s.rolloff_wavelength = r.number("surface.rolloff_wavelength");
  if (r.has("surface.cutoff_wavelength"))
    s.cutoff_wavelength = r.number("surface.cutoff_wavelength");
}

void check_rough(const Reader& r, const RoughSpec& s) {
  if (s.rms_height.has_value() == s.rms_slope.has_value())
    r.fail("surface.type = rough needs exactly one of surface.rms_height and surface.rms_slope");
  r.require("surface.seed",
            " for surface.type = rough (results are reproducible only with an "
            "explicit seed)");
  if (s.rolloff_wavelength > 0 && s.cutoff_wavelength > 0 &&
      s.cutoff_wavelength >= s.rolloff_wavelength)
    r.fail("surface.cutoff_wavelength = " + format_number(s.cutoff_wavelength) +
           " must be shorter than surface.rolloff_wavelength = " +
           format_number(s.rolloff_wavelength));
}

void read_surface(const Reader& r, const fs::path& base, SurfaceSpec& s) {
  if (r.has("surface.type")) s.type = static_cast<SurfaceType>(r.option("surface.type"));
  if (r.has("surface.radius")) s.radius = r.number("surface.radius");
  read_rough(r, s.rough);
  if (r.has("surface.dataset")) s.dataset = r.raw("surface.dataset");
  if (r.has("surface.spacing")) s.spacing = r.number("surface.spacing");
  if (r.has("surface.layout")) s.layout = static_cast<HeightLayout>(r.option("surface.layout"));
  const bool is_file = s.type == SurfaceType::file;
  if (r.has("surface.file")) s.file = r.path("surface.file", base, is_file);
  if (s.type == SurfaceType::sphere) r.require("surface.radius", " for surface.type = sphere");
  if (s.type == SurfaceType::rough) check_rough(r, s.rough);
  if (is_file) r.require("surface.file", " for surface.type = file");
}

// The table's header decides what it can drive; catch a mismatch here rather than mid-run.
void check_table(const Reader& r, const LoadSpec& l) {
  std::vector<std::string> header;
  try {
    header = csv::read_header(l.table);
  } catch (const InputError& e) {
    r.fail_value("load.table", std::string("cannot be read: ") + e.what());
  }
  const std::vector<std::string> known = {"time", "Fz", "delta", "Fx", "Fy", "Ux", "Uy"};
  std::set<std::string> cols;
  for (const auto& c : header) {
    if (std::find(known.begin(), known.end(), c) == known.end())
      r.fail_value("load.table", "has an unknown column '" + printable(c) + "'" +
                                     suggestion(c, known) +
                                     "; columns: time, Fz, delta, Fx, "
                                     "Fy, Ux, Uy");
    cols.insert(c);
  }
  if (!cols.count("time")) r.fail_value("load.table", "has no 'time' column in its header row");
  const bool normal_given = l.normal_force || l.indentation;
  if (!normal_given && !cols.count("Fz") && !cols.count("delta"))
    r.fail_value("load.table",
                 "has neither Fz nor delta, and neither load.normal_force nor "
                 "load.indentation is given");
  if (normal_given && (cols.count("Fz") || cols.count("delta")))
    r.fail_value("load.table",
                 "has an Fz or delta column as well as a constant normal load "
                 "key; give one");
  const bool force_cols = cols.count("Fx") || cols.count("Fy");
  const bool disp_cols = cols.count("Ux") || cols.count("Uy");
  if (l.control == Control::force && disp_cols)
    r.fail_value("load.table", "has Ux/Uy columns but load.control = force");
  if (l.control == Control::displacement && force_cols)
    r.fail_value("load.table", "has Fx/Fy columns but load.control = displacement");
}

void read_load_values(const Reader& r, const fs::path& base, LoadSpec& l) {
  if (r.has("load.normal_force")) l.normal_force = r.number("load.normal_force");
  if (r.has("load.indentation")) l.indentation = r.number("load.indentation");
  if (r.has("load.path")) l.path = static_cast<PathType>(r.option("load.path"));
  if (r.has("load.control")) l.control = static_cast<Control>(r.option("load.control"));
  if (r.has("load.amplitude")) l.amplitude = r.number("load.amplitude");
  if (r.has("load.displacement_amplitude"))
    l.displacement_amplitude = r.number("load.displacement_amplitude");
  if (r.has("load.direction")) l.direction = r.number("load.direction");
  if (r.has("load.cycles")) l.cycles = static_cast<int>(r.count("load.cycles"));
  if (r.has("load.steps_per_cycle"))
    l.steps_per_cycle = static_cast<int>(r.count("load.steps_per_cycle"));
  if (r.has("load.steps")) l.steps = static_cast<int>(r.count("load.steps"));
  if (r.has("load.table")) l.table = r.path("load.table", base, l.path == PathType::table);
  if (r.has("load.allow_large_shift")) l.allow_large_shift = r.boolean("load.allow_large_shift");
  if (r.has("load.tolerance")) l.tolerance = r.number("load.tolerance");
  if (r.has("load.substeps")) l.substeps = static_cast<int>(r.count("load.substeps"));
  if (r.has("load.interpolation"))
    l.interpolation = static_cast<LoadInterpolation>(r.option("load.interpolation"));
}

void check_amplitudes(const Reader& r, const LoadSpec& l) {
  if (l.path != PathType::ramp && l.path != PathType::sine) return;
  if (l.control == Control::force) {
    r.require("load.amplitude", " for a force-controlled ramp or sine");
    if (l.amplitude >= 1.0)
      r.fail_value("load.amplitude",
                   "is impossible: a tangential force >= mu Fz cannot be held by friction "
                   "(gross sliding); use a value < 1, or load.control = displacement");
    if (l.amplitude <= 0.0) r.fail_value("load.amplitude", "is out of range (0, 1)");
    // A fraction of mu Fz below 1e-100 is a tangential load the arithmetic cannot carry.
    if (l.amplitude < kMinMagnitude) r.fail_value("load.amplitude", "is below 1e-100");
  } else {
    r.require("load.displacement_amplitude", " for a displacement-controlled ramp or sine");
    r.magnitude("load.displacement_amplitude");
  }
  if (l.path == PathType::sine &&
      static_cast<long long>(l.cycles) * l.steps_per_cycle > std::numeric_limits<int>::max())
    r.fail("load.cycles x load.steps_per_cycle is too many steps");
}

void read_load(const Reader& r, const fs::path& base, LoadSpec& l) {
  read_load_values(r, base, l);
  if (l.normal_force && l.indentation)
    r.fail("load.normal_force and load.indentation are both given; give exactly one");
  if (l.path == PathType::table) {
    r.require("load.table", " for load.path = table");
    check_table(r, l);
  } else if (!l.normal_force && !l.indentation) {
    r.fail("missing required key 'load.normal_force' or 'load.indentation'");
  }
  check_amplitudes(r, l);
}

// solver.stiffness: every | turning | none, or the wave-1 booleans (true = every, false = none;
// any spelling Reader::boolean takes). A value that is neither names the three modes.
StiffnessMode read_stiffness(const Reader& r) {
  static const std::vector<std::string> booleans = {"true",  "yes", "1", "on",
                                                    "false", "no",  "0", "off"};
  const std::string v = lower(r.raw("solver.stiffness"));
  if (std::find(booleans.begin(), booleans.end(), v) != booleans.end())
    return r.boolean("solver.stiffness") ? StiffnessMode::every : StiffnessMode::none;
  return static_cast<StiffnessMode>(r.option("solver.stiffness"));
}

void read_solver(const Reader& r, SolverSpec& s) {
  if (r.has("solver.tolerance")) s.tolerance = r.number("solver.tolerance");
  if (r.has("solver.max_iterations"))
    s.max_iterations = static_cast<int>(r.count("solver.max_iterations"));
  if (r.has("solver.coupling")) s.coupling = static_cast<Coupling>(r.option("solver.coupling"));
  if (r.has("solver.coupling_tolerance"))
    s.coupling_tolerance = r.number("solver.coupling_tolerance");
  if (r.has("solver.coupling_iterations"))
    s.coupling_iterations = static_cast<int>(r.count("solver.coupling_iterations"));
  if (r.has("solver.threads")) s.threads = static_cast<int>(r.count("solver.threads"));
  if (r.has("solver.algorithm"))
    s.algorithm = static_cast<TangentialAlgorithm>(r.option("solver.algorithm"));
  if (r.has("solver.stiffness")) s.stiffness = read_stiffness(r);
  if (r.has("solver.fft_plan")) s.fft_plan = static_cast<FftPlanning>(r.option("solver.fft_plan"));
  if (r.has("solver.monotone"))
    s.monotone = static_cast<MonotoneMethod>(r.option("solver.monotone"));
  if (r.has("solver.predictor"))
    s.predictor = static_cast<PredictorMode>(r.option("solver.predictor"));
  if (r.has("solver.precondition")) {
    // The table spells the choices automatic|on|off (the README's order).
    static constexpr Precondition kinds[] = {Precondition::automatic, Precondition::on,
                                             Precondition::off};
    s.precondition = kinds[r.option("solver.precondition")];
  }
  if (r.has("solver.fft_precision"))
    s.fft_precision = static_cast<FftPrecision>(r.option("solver.fft_precision"));
  // Float convolutions put a round-off floor under every residual. Without an explicit
  // tolerance the floor is the default (written to the resolved scenario); an explicit one
  // below it is refused here, so `fretbem check` catches it and no solve stagnates to
  // max_iterations first.
  if (s.fft_precision == FftPrecision::float32) {
    if (!r.has("solver.tolerance"))
      s.tolerance = kFloatFftMinTolerance;
    else if (s.tolerance < kFloatFftMinTolerance)
      r.fail_value("solver.tolerance", "is below " + format_number(kFloatFftMinTolerance) +
                                           ", the smallest tolerance float FFTs can reach "
                                           "(solver.fft_precision = float): raise it or use "
                                           "solver.fft_precision = double");
  }
}

// "pressure, traction_x, ...": the names output.fields accepts.
std::string field_list() {
  std::string list;
  for (const auto& f : kFieldNames) list += (list.empty() ? "" : ", ") + f;
  return list;
}

std::vector<std::string> read_fields(const Reader& r) {
  std::vector<std::string> out;
  const std::string list = trim(r.raw("output.fields"));
  if (list.empty() || list == "none") return out;
  for (const auto& f : csv::split_line(list)) {
    if (std::find(kFieldNames.begin(), kFieldNames.end(), f) == kFieldNames.end())
      r.fail_value("output.fields", "names an unknown field '" + printable(f) + "'" +
                                        suggestion(f, kFieldNames) + "; fields: " + field_list());
    if (std::find(out.begin(), out.end(), f) == out.end()) out.push_back(f);
  }
  return out;
}

void read_output(const Reader& r, OutputSpec& o) {
  if (r.has("output.dir")) {
    if (r.raw("output.dir").empty()) r.fail_value("output.dir", "is empty");
    o.dir = r.raw("output.dir");
  }
  if (r.has("output.fields")) o.fields = read_fields(r);
  if (r.has("output.fields_every"))
    o.fields_every = static_cast<int>(r.count("output.fields_every"));
  if (r.has("output.checkpoint_every"))
    o.checkpoint_every = static_cast<int>(r.count("output.checkpoint_every"));
}

void read_wear(const Reader& r, WearSpec& w) {
  if (r.has("wear.law")) w.law = static_cast<WearLaw>(r.option("wear.law"));
  if (r.has("wear.coefficient")) w.coefficient = r.number("wear.coefficient");
  if (r.has("wear.cycles")) w.cycles = r.number("wear.cycles");
  if (r.has("wear.integrator"))
    w.integrator = static_cast<WearIntegrator>(r.option("wear.integrator"));
  if (r.has("wear.rtol")) w.rtol = r.number("wear.rtol");
  if (r.has("wear.atol")) w.atol = r.number("wear.atol");
  if (r.has("wear.newton")) w.newton = static_cast<WearNewton>(r.option("wear.newton"));
  if (r.has("wear.indenter_share")) w.indenter_share = r.number("wear.indenter_share");
  if (w.law == WearLaw::none) return;
  r.require("wear.coefficient", " when wear.law is not none");
  r.require("wear.cycles", " when wear.law is not none");
  if (w.integrator == WearIntegrator::cycle && w.cycles != std::floor(w.cycles))
    r.fail_value("wear.cycles", "is not a whole number (wear.integrator = cycle)");
}

void read_friction(const Reader& r, const LoadSpec& l, double mu, FrictionSpec& f) {
  if (r.has("friction.law")) f.law = static_cast<FrictionLawKind>(r.option("friction.law"));
  if (r.has("friction.mu_kinetic")) f.mu_kinetic = r.number("friction.mu_kinetic");
  if (r.has("friction.mu_final")) f.mu_final = r.number("friction.mu_final");
  if (r.has("friction.evolution"))
    f.evolution = static_cast<FrictionVariable>(r.option("friction.evolution"));
  if (r.has("friction.scale")) f.scale = r.number("friction.scale");
  double lowest = mu;
  if (f.law == FrictionLawKind::static_kinetic) {
    r.require("friction.mu_kinetic", " for friction.law = static_kinetic");
    lowest = std::min(mu, f.mu_kinetic);
  }
  if (f.law == FrictionLawKind::evolving) {
    r.require("friction.mu_final", " for friction.law = evolving");
    r.require("friction.scale", " for friction.law = evolving");
    lowest = std::min(mu, f.mu_final);
  }
  // Force-controlled amplitudes are fractions of material.mu F_z: a law that lowers mu below
  // the amplitude would ask friction for more than it can hold.
  const bool force_path =
      l.control == Control::force && (l.path == PathType::ramp || l.path == PathType::sine);
  if (force_path && l.amplitude * mu >= lowest)
    r.fail_value("load.amplitude", "times material.mu reaches the lowest friction coefficient " +
                                       format_number(lowest) +
                                       " of friction.law: friction could not hold the load; "
                                       "lower it or use load.control = displacement");
}

// A friction law whose coefficient follows the accumulated slip or dissipation needs the
// physical history of every cycle: the ODE integrators' wear map is the steady cycle of a
// surface from a traction-free state (docs/wear.md), which would restart the evolution at mu_0
// in every evaluation and integrate the whole run at the first cycle's friction.
void check_wear_friction(const Reader& r, const WearSpec& w, const FrictionSpec& f) {
  if (w.law != WearLaw::none && f.law == FrictionLawKind::evolving &&
      w.integrator != WearIntegrator::cycle)
    r.fail_value("friction.law",
                 "needs wear.integrator = cycle in a wear run (the ODE integrators' "
                 "wear map restarts the friction evolution in every evaluation)");
}

// The sub-steps a row whose normal load changes is solved in, where they differ from
// load.substeps' default. Error-controlled steps and sub-steps re-solve a row's load from its
// start state; the wear integrators restore and replay rows on frozen surfaces with their own
// step control (docs/wear.md): a wear run solves its rows whole, and refuses either key asking
// otherwise. Under solver.coupling = coupled rows are solved whole unless load.substeps is
// given: the coupled bound moves within the coupling's alternation and coupled runs keep the
// first-order rules at contact entry and loss, so the sub-steps do not give the default's
// second order there. Measured (docs/algorithms.md, "Sub-steps of a row"): the coupled sphere
// under F_z = P (1 + 0.3 sin 2 pi t) at 32 rows a period, n = 32, third period's dissipation
// changed by 2.6e-3, 2.4e-3, 1.4e-3 of itself from 1 to 2, 4, 8 sub-steps (Cerruti: 4.2e-4,
// 5.2e-5, 3.8e-6), at 6.1 times the convolutions of one solve a row in 4 sub-steps.
void resolve_load_substeps(const Reader& r, const WearSpec& w, const SolverSpec& s, LoadSpec& l) {
  if (w.law != WearLaw::none) {
    if (l.tolerance > 0.0)
      r.fail_value("load.tolerance", "is not supported in wear runs (wear.law is not none); use 0");
    if (r.has("load.substeps") && l.substeps > 1)
      r.fail_value("load.substeps", "is not supported in wear runs (wear.law is not none); use 1");
    l.substeps = 1;
  }
  if (s.coupling == Coupling::coupled && !r.has("load.substeps")) l.substeps = 1;
}

}  // namespace fretbem::scenario_detail
