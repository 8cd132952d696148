// The scenario key table (README "Scenario files"). Ranges carry the measurement or limit that
// sets them; the readers in sections.cpp apply them through Reader::number, count and option.
#include "fretbem/scenario/key_table.hpp"

#include <algorithm>
#include <stdexcept>

#include "fretbem/scenario/scenario.hpp"

namespace fretbem {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Counts (cycles, steps, iterations) stay inside a 32-bit int with room for products.
constexpr double kMaxCount = 1 << 30;
// Grid sides keep nx*ny and the 2nx x 2ny padded FFT grid inside a 32-bit int index.
constexpr double kMaxSide = 65536;

ScenarioKey magnitude(std::string_view key, std::string_view unit, std::string_view doc) {
  return {key, KeyType::magnitude, unit, 0.0, kInf, true, true, {}, "", doc};
}

ScenarioKey integer(std::string_view key, double lo, double hi, std::string_view def,
                    std::string_view doc) {
  return {key, KeyType::integer, "1", lo, hi, false, false, {}, def, doc};
}

ScenarioKey choice(std::string_view key, std::vector<std::string> choices, std::string_view def,
                   std::string_view doc) {
  return {key, KeyType::choice, "", -kInf, kInf, false, false, std::move(choices), def, doc};
}

ScenarioKey boolean(std::string_view key, std::string_view doc) {
  return {key, KeyType::boolean, "", -kInf, kInf, false, false, {}, "false", doc};
}

ScenarioKey real(std::string_view key, std::string_view unit, double lo, bool lo_open, double hi,
                 bool hi_open, std::string_view def, std::string_view doc) {
  return {key, KeyType::real, unit, lo, hi, lo_open, hi_open, {}, def, doc};
}

ScenarioKey typed(std::string_view key, KeyType type, std::string_view unit, std::string_view def,
                  std::string_view doc) {
  return {key, type, unit, -kInf, kInf, false, false, {}, def, doc};
}

// Over 80 lines on purpose: one entry per key and nothing else, so its length is the number of
// keys; split into parts, the one table a key is looked up in would be several.
std::vector<ScenarioKey> make_table() {
  return {
      magnitude("material.E", "Pa", "half-space Young's modulus (required)"),
      real("material.nu", "1", 0.0, false, 0.5, true, "", "half-space Poisson ratio (required)"),
      magnitude("material.E2", "Pa", "second (indenter) body's Young's modulus; rigid if unset"),
      real("material.nu2", "1", 0.0, false, 0.5, true, "", "second body's Poisson ratio"),
      {"material.mu",
       KeyType::magnitude,
       "1",
       0.0,
       kInf,
       true,
       true,
       {},
       "0.3",
       "Coulomb friction coefficient"},
      integer("grid.n", 2, kMaxSide, "", "nodes per side"),
      integer("grid.nx", 2, kMaxSide, "", "nodes along x (with grid.ny)"),
      integer("grid.ny", 2, kMaxSide, "", "nodes along y (with grid.nx)"),
      magnitude("grid.length", "m", "side of the domain along x; cells are square"),
      boolean("grid.periodic", "periodic surface instead of the free (zero-padded) boundary"),
      boolean("grid.allow_edge_contact", "run a sphere with load on the grid's outermost cells"),
      choice("surface.type", {"sphere", "flat", "rough", "file"}, "sphere", "indenter shape"),
      magnitude("surface.radius", "m", "sphere radius"),
      real("surface.hurst", "1", 0.0, true, 1.0, false, "0.8", "rough: Hurst exponent H"),
      magnitude("surface.rms_height", "m", "rough: rms height (or surface.rms_slope)"),
      magnitude("surface.rms_slope", "1", "rough: rms slope (or surface.rms_height)"),
      choice("surface.method", {"midpoint", "fourier"}, "midpoint", "rough: generator"),
      typed("surface.seed", KeyType::seed, "1", "1", "rough: random seed (required there)"),
      typed("surface.rolloff_wavelength", KeyType::wavelength, "m", "0",
            "fourier PSD flat above this wavelength; 0: none"),
      typed("surface.cutoff_wavelength", KeyType::wavelength, "m", "0",
            "fourier PSD zero below this wavelength; 0: none"),
      typed("surface.file", KeyType::path, "", "", "height map file"),
      typed("surface.dataset", KeyType::text, "", "", "HDF5 dataset or .npz entry of the map"),
      choice("surface.layout", {"yx", "xy"}, "yx", "axis order of the height map"),
      magnitude("surface.spacing", "m", "the height map's grid spacing"),
      magnitude("load.normal_force", "N", "constant normal force"),
      magnitude("load.indentation", "m", "constant normal approach"),
      choice("load.path", {"none", "ramp", "sine", "table"}, "none", "tangential load path"),
      choice("load.control", {"force", "displacement"}, "force",
             "what the tangential path imposes"),
      typed("load.amplitude", KeyType::real, "1", "0",
            "force control: tangential amplitude / (mu F_z), < 1"),
      typed("load.displacement_amplitude", KeyType::real, "m", "0",
            "displacement control: tangential amplitude"),
      // Past 1e6 degrees the angle reduced mod 360 keeps fewer than 10 digits.
      real("load.direction", "degree", -1e6, false, 1e6, false, "0",
           "angle of the ramp or sine in the x-y plane"),
      integer("load.cycles", 1, kMaxCount, "1", "sine: cycles"),
      integer("load.steps_per_cycle", 4, kMaxCount, "64", "sine: steps per period"),
      integer("load.steps", 1, kMaxCount, "20", "ramp: steps"),
      typed("load.table", KeyType::path, "", "", "CSV load table"),
      boolean("load.allow_large_shift", "run tangential shifts past one contact radius"),
      real("load.tolerance", "1", 0.0, false, 0.1, false, "0",
           "relative error per period of steps whose normal load changes; 0: off"),
      // 4: the fewest that meet 5e-4 of the step limit at 32 rows a period on the sphere,
      // displacement and rough benches under either interpolation (docs/algorithms.md); at
      // most the step control's 256 a row (kMaxSubsteps, history/step_control.hpp).
      integer("load.substeps", 1, 256, "4",
              "equal solves a row whose normal load changes (no load.tolerance; coupled: 1); 1: one"),
      choice("load.interpolation", {"linear", "cubic"}, "linear",
             "table: load between rows on straight lines or a not-a-knot cubic spline"),
      // Below 1e-14 no solve can get: round-off of the double sums over the grid leaves
      // relative residuals of ~6e-15 already at n = 16 (1e-300 ran 5000 iterations into exit 3).
      real("solver.tolerance", "1", 1e-14, false, 1e-2, false, "1e-08",
           "relative residual of every solve"),
      integer("solver.max_iterations", 1, kMaxCount, "5000", "iterations per solve"),
      choice("solver.coupling", {"analogy", "cerruti", "coupled"}, "analogy",
             "normal-tangential coupling model"),
      real("solver.coupling_tolerance", "1", 0.0, true, 1e-1, false, "1e-06",
           "coupled: rms change that ends the alternation"),
      integer("solver.coupling_iterations", 1, 100000, "50", "coupled: alternations per step"),
      integer("solver.threads", 0, 4096, "0", "FFT threads from n = 512; 0: all cores"),
      choice("solver.algorithm", {"projected", "partition"}, "projected", "tangential solver"),
      // Also takes the booleans (true = every, false = none).
      choice("solver.stiffness", {"every", "turning", "none"}, "every",
             "which steps compute the differential stiffness kx"),
      choice("solver.fft_plan", {"auto", "estimate", "measure"}, "estimate",
             "how FFTW plans are chosen"),
      choice("solver.fft_precision", {"double", "float"}, "double", "convolution precision"),
      choice("solver.precondition", {"automatic", "on", "off"}, "automatic",
             "Fourier preconditioning of the CG solves"),
      choice("solver.monotone", {"incremental", "shortcut"}, "incremental",
             "virgin monotone ramps solved incrementally or by superposition"),
      choice("solver.predictor", {"auto", "none", "cycle"}, "auto",
             "start tangential increments from the previous cycle's traction"),
      typed("output.dir", KeyType::text, "", "out", "output folder"),
      typed("output.fields", KeyType::fields, "", "none", "fields to save"),
      integer("output.fields_every", 0, kMaxCount, "0", "save fields every N steps"),
      integer("output.checkpoint_every", 0, kMaxCount, "0", "checkpoint every N steps"),
      choice("wear.law", {"none", "archard", "energy"}, "none", "wear law"),
      magnitude("wear.coefficient", "1/Pa", "Archard k or energy alpha"),
      // Under one cycle there is no cycle to average the wear rate over (1e-300 failed inside
      // ARKODE, flag -22); past 2^53 the cycle count is no longer an exact double.
      real("wear.cycles", "1", 1.0, false, 9007199254740992.0, false, "", "cycle count N"),
      choice("wear.integrator", {"arkode", "cycle", "erk", "dirk"}, "arkode", "wear integrator"),
      // Measured on fretting_wear at n = 32, dirk, N = 1e5: rtol = 1 puts the worn depth 3.5 %
      // off, 1e300 3.8 times (exit 0); 1e-300 fails inside ARKODE. 1e-14 runs.
      real("wear.rtol", "1", kMinWearRelTolerance, false, kMaxWearRelTolerance, false, "0.001",
           "ARKODE relative tolerance"),
      magnitude("wear.atol", "m", "ARKODE absolute tolerance; unset: rtol x delta0"),
      choice("wear.newton", {"frozen", "krylov"}, "frozen", "implicit Newton iteration"),
      real("wear.indenter_share", "1", 0.0, false, 1.0, false, "1",
           "share of the worn depth on the indenter"),
      choice("friction.law", {"constant", "static_kinetic", "evolving"}, "constant",
             "friction law"),
      magnitude("friction.mu_kinetic", "1", "static_kinetic: mu once a node slips"),
      magnitude("friction.mu_final", "1", "evolving: mu after a long history"),
      choice("friction.evolution", {"dissipation", "slip_path"}, "dissipation",
             "evolving: what mu follows"),
      magnitude("friction.scale", "J/m^2 or m", "evolving: X over which mu moves 1 - 1/e"),
  };
}

}  // namespace

const std::vector<ScenarioKey>& scenario_keys() {
  static const std::vector<ScenarioKey> table = make_table();
  return table;
}

const ScenarioKey& scenario_key(std::string_view key) {
  const auto& table = scenario_keys();
  const auto it =
      std::find_if(table.begin(), table.end(), [&](const ScenarioKey& k) { return k.key == key; });
  if (it == table.end()) throw std::out_of_range("no scenario key " + std::string(key));
  return *it;
}

const std::string& choice_name(std::string_view key, std::size_t i) {
  return scenario_key(key).choices.at(i);
}

const std::vector<std::string>& scenario_sections() {
  static const std::vector<std::string> sections = {"material", "grid",   "surface", "load",
                                                    "solver",   "output", "wear",    "friction"};
  return sections;
}

}  // namespace fretbem
