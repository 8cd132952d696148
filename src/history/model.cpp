#include "fretbem/history/model.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/format.hpp"
#include "fretbem/core/input_warning.hpp"
#include "fretbem/core/resources.hpp"
#include "fretbem/elastic/fft_wisdom.hpp"
#include "fretbem/history/cost_estimate.hpp"
#include "fretbem/history/cycle_predictor.hpp"
#include "fretbem/history/preflight.hpp"
#include "fretbem/history/step_control.hpp"

namespace fretbem {

namespace {

std::string shape_text(const Field& z) {
  return std::to_string(z.rows()) + " x " + std::to_string(z.cols());
}

// x3p stores the increments as decimal text: agree to 1e-6 relative (6+ digits written).
bool same_spacing(double a, double b) {
  return std::abs(a - b) <= 1e-6 * std::max(a, b);
}

// The map's spacing from the file (x3p, .npz, HDF5) or surface.spacing must be grid.length / n;
// a given surface.spacing must also agree with the file's. A map with neither (.npy, text, or
// files without the metadata) is taken at grid.length / n, so that scenarios written without
// surface.spacing keep running, with a warning that nothing checked it.
void check_spacing(const SurfaceSpec& s, const Grid& g, const HeightMap& m,
                   const std::string& where) {
  for (const auto& [name, d] : {std::pair{"x", m.dx}, std::pair{"y", m.dy}}) {
    if (d && s.spacing && !same_spacing(*d, *s.spacing))
      throw InputError(where + " spacing along " + name + " is " + format_number(*d) +
                       " m in the file but surface.spacing = " + format_number(*s.spacing) + " m");
    const std::optional<double> spacing = d ? d : s.spacing;
    if (spacing && !same_spacing(*spacing, g.h))
      throw InputError(where + " spacing along " + name + " is " + format_number(*spacing) +
                       (d ? " m in the file" : " m (surface.spacing)") +
                       " but grid.length / n = " + format_number(g.h) + " m; set grid.length = " +
                       format_number(*spacing * g.nx) + " (a height map is never rescaled)");
  }
  if (!m.dx && !m.dy && !s.spacing)
    input_warning(where +
                  " carries no spacing and surface.spacing is not given: its cells "
                  "are taken as grid.length / n = " +
                  format_number(g.h) + " m; set surface.spacing to have that checked");
}

// A height map must fit the grid as it stands: a transposed file or a file whose own spacing
// (x3p) disagrees with grid.length / n is an error, never a silent transpose or rescale.
Field file_surface(const Scenario& sc) {
  const SurfaceSpec& s = sc.surface;
  const Grid& g = sc.grid;
  HeightMap m = read_height_map(s.file, s.dataset, s.layout);
  const std::string where = s.file.string() + ": height map";
  const Field& z = m.z;
  if (z.rows() != g.nx || z.cols() != g.ny) {
    const bool x3p = s.file.extension() == ".x3p" || s.file.extension() == ".X3P";
    std::string hint;
    if (!x3p && z.rows() == g.ny && z.cols() == g.nx)
      hint = s.layout == HeightLayout::yx
                 ? "; the file looks transposed: set surface.layout = xy if its first index "
                   "runs along x"
                 : "; the file looks transposed: set surface.layout = yx if its rows run "
                   "along y";
    throw InputError(where + " is " + shape_text(z) + " (x by y, surface.layout = " +
                     (s.layout == HeightLayout::yx ? "yx" : "xy") + ") but the grid is " +
                     std::to_string(g.nx) + " x " + std::to_string(g.ny) + hint);
  }
  check_heights(sc, z);  // before the spacing's warning: a refused map gets one line
  check_spacing(s, g, m, where);
  return std::move(m.z);
}

// The ODE wear integrators' wear map is the steady cycle of a surface from a traction-free
// state (docs/wear.md): the periodic state of a path whose tangential load stays on one line
// through zero (Masing). A table moving off that line (2-D motion) has history-dependent
// periodic and shakedown states, so that map is not the run's: measured at n = 32 (table
// Fx, Fy = (2, 1), (0, 2), (-2, 1), (0, 0) N, k = 1e-11, N = 1000), arkode ended at 1.54x
// the max worn depth of wear.integrator = cycle, and still at 1.31x with four more periods
// run before the measured one (tools/bench/wear_sweep.py). Refused, as evolving friction is.
void check_wear_path(const Scenario& sc, const LoadPath& path) {
  if (sc.wear.law == WearLaw::none || sc.wear.integrator == WearIntegrator::cycle) return;
  if (sc.load.path == PathType::table && !path.collinear_direction())
    throw InputError(
        "load.table: its tangential load leaves one line through zero (2-D motion): a wear "
        "run on it needs wear.integrator = cycle (the ODE integrators' wear map, the steady "
        "cycle from a traction-free state, is not the periodic state of a 2-D path)");
}

Field generated_or_loaded_surface(const Scenario& sc) {
  const Grid& g = sc.grid;
  switch (sc.surface.type) {
    case SurfaceType::sphere:
      return sphere_surface(g, sc.surface.radius);
    case SurfaceType::flat:
      return flat_surface(g);
    case SurfaceType::rough:
      return rough_surface(g, sc.surface.rough);
    case SurfaceType::file:
      return file_surface(sc);
  }
  throw InputError("surface.type: unknown");
}

}  // namespace

// Every surface, whoever asks (run, check, `fretbem surface`), within the bound of the inputs.
Field make_surface(const Scenario& sc) {
  Field z = generated_or_loaded_surface(sc);
  check_heights(sc, z);
  return z;
}

bool use_cycle_predictor(const Scenario& sc, const LoadPath& path) {
  if (sc.solver.predictor != PredictorMode::automatic)
    return sc.solver.predictor == PredictorMode::cycle;
  const std::vector<char> later = CyclePredictor::repeated_later(path.steps);
  if (std::find(later.begin(), later.end(), 1) == later.end()) return false;
  const double have = usable_memory_bytes();
  return have <= 0 || estimate_memory(sc, true, predictor_bytes_per_cell(sc, path),
                                      repeat_bytes_per_cell(sc, path))
                              .total() <= have;
}

// Against what the process may use: inside a batch job (Slurm, containers) the cgroup limit is
// smaller than the node's RAM, and exceeding it kills the job instead of failing cleanly.
void check_memory(const Scenario& sc, const LoadPath& path, bool cycle_predictor) {
  const double have = usable_memory_bytes();
  const double need = estimate_memory(sc, cycle_predictor, predictor_bytes_per_cell(sc, path),
                                      repeat_bytes_per_cell(sc, path))
                          .total();
  if (have <= 0 || need <= have) return;  // unknown: let the allocator decide
  std::ostringstream msg;
  msg.precision(3);
  msg << "grid " << sc.grid.nx << " x " << sc.grid.ny << " needs about " << need / (1 << 30)
      << " GiB of memory but this machine has " << have / (1 << 30) << " GiB: reduce grid.n";
  throw InputError(msg.str());
}

// FFT threads: solver.threads (0: all usable cores, affinity mask, SLURM_CPUS_PER_TASK) from
// n = kThreadedFromN up, one thread below. The transforms of a small grid take microseconds,
// less than the hand-over between threads: a second thread there costs many times the CPU of one
// and, on a loaded machine, the wall time too (libgomp's workers spin between FFTW's parallel
// regions). Measured break-even: docs/performance.md, "FFT threads".
constexpr int kThreadedFromN = 512;

int fft_threads(const SolverSpec& s, const Grid& g) {
  if (std::max(g.nx, g.ny) < kThreadedFromN) return 1;
  return s.threads > 0 ? s.threads : usable_cpus();
}

bool stiffness_wanted(const Model& model, int step, bool turning) {
  if (!model.stiffness) return false;
  return model.scenario.solver.stiffness == StiffnessMode::every || step == 0 || turning;
}

std::unique_ptr<Model> prepare_model(const Scenario& sc) {
  auto m = std::make_unique<Model>();
  m->scenario = sc;
  m->path = make_load_path(sc);
  m->cycle_predictor = use_cycle_predictor(sc, m->path);
  check_memory(sc, m->path, m->cycle_predictor);  // before the surface, kernels and FFT buffers
  m->surface0 = make_surface(sc);
  m->surface = m->surface0;
  check_before_solve(sc, m->path, m->surface0);
  m->wear = make_wear_model(sc.wear);
  check_wear_path(sc, m->path);
  m->friction = make_friction_law(sc.friction, sc.material.mu, sc.grid.periodic);
  return m;
}

FftOptions fft_options(const Scenario& sc) {
  FftOptions fft;
  fft.threads = fft_threads(sc.solver, sc.grid);
  fft.precision = sc.solver.fft_precision;
  fft.measure =
      sc.solver.fft_plan == FftPlanning::measure ||
      (sc.solver.fft_plan == FftPlanning::automatic && fft_wisdom::persistent(fft.precision));
  return fft;
}

// What a run on a grid distributed over ranks does not do yet (docs/mpi-grid.md): refused
// with the key named, before the operators are built (coupled and float32 transforms are
// refused by HalfSpace).
void refuse_undistributed(const Scenario& sc, const Communicator& comm) {
  if (!comm.distributed()) return;
  const std::string k = " under mpirun -n " + std::to_string(comm.size()) + ": ";
  if (sc.friction.law != FrictionLawKind::constant)
    throw InputError("friction.law" + k +
                     "only the constant law runs on a grid distributed over ranks; run it "
                     "without mpirun");
  if (sc.solver.monotone == MonotoneMethod::shortcut)
    throw InputError("solver.monotone = shortcut" + k +
                     "not available on a grid distributed over ranks; use incremental");
  if (sc.grid.ny < comm.size())
    throw InputError("grid.n" + k + "the grid has " + std::to_string(sc.grid.ny) +
                     " rows, fewer than the ranks; use fewer ranks");
}

std::unique_ptr<Model> build_model(const Scenario& sc, const Communicator& comm) {
  auto m = prepare_model(sc);
  refuse_undistributed(sc, comm);
  m->half_space =
      std::make_unique<HalfSpace>(sc.grid, sc.material, sc.solver.coupling, fft_options(sc), comm);
  if (comm.min(double(m->half_space->local_rows())) < 1.0)
    throw InputError("grid.n under mpirun -n " + std::to_string(comm.size()) +
                     ": some rank holds no row of the grid; use fewer ranks");
  // parse_scenario refuses these already; a Scenario built in code reaches this check.
  m->half_space->require_tolerance(sc.solver.tolerance, "solver.tolerance");
  NormalOptions nopt{sc.solver.tolerance, sc.solver.max_iterations, sc.solver.precondition};
  m->normal = std::make_unique<NormalSolver>(*m->half_space, nopt);
  if (sc.solver.monotone == MonotoneMethod::shortcut) {
    nopt.precondition_by_set = true;
    m->corrective = std::make_unique<NormalSolver>(*m->half_space, nopt);
  }
  const auto dir = m->path.collinear_direction();
  if (sc.solver.coupling == Coupling::analogy && dir)
    m->tangential_operator = std::make_unique<TangentialOperator>(*m->half_space, *dir);
  else
    m->tangential_operator = std::make_unique<TangentialOperator>(*m->half_space);
  TangentialOptions topt{sc.solver.tolerance, sc.solver.max_iterations};
  topt.precondition = sc.solver.precondition;
  // The chosen algorithm, with the other one and sub-steps as fallbacks (docs/stability.md).
  std::unique_ptr<TangentialSolver> projected =
      std::make_unique<ProjectedCgSolver>(*m->tangential_operator, topt);
  std::unique_ptr<TangentialSolver> partition =
      std::make_unique<PartitionSolver>(*m->tangential_operator, topt);
  if (sc.solver.algorithm == TangentialAlgorithm::partition) std::swap(projected, partition);
  m->tangential = std::make_unique<FallbackTangentialSolver>(
      *m->tangential_operator, sc.solver.tolerance, std::move(projected), std::move(partition));
  // The stiffness solve's own floor of 1e-9 is raised to what float FFTs can reach: it is an
  // internal accuracy choice, not the user's tolerance (which is at least that floor).
  if (sc.solver.stiffness != StiffnessMode::none)
    m->stiffness = std::make_unique<StiffnessSolver>(
        *m->tangential_operator,
        std::max({sc.solver.tolerance, 1e-9, m->half_space->min_tolerance()}),
        sc.solver.max_iterations, sc.solver.precondition);
  return m;
}

}  // namespace fretbem
