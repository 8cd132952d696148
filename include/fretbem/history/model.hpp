// Model: everything a run needs, built once from a validated Scenario — grid, material,
// surface, half-space operator and the solvers on it (docs/architecture.md).
#pragma once

#include <memory>
#include <string>

#include "fretbem/contact/normal_solver.hpp"
#include "fretbem/contact/stiffness.hpp"
#include "fretbem/contact/tangential_solver.hpp"
#include "fretbem/friction/law.hpp"
#include "fretbem/history/load_path.hpp"
#include "fretbem/scenario/scenario.hpp"
#include "fretbem/wear_law/law.hpp"

namespace fretbem {

struct Model {
  Scenario scenario;
  LoadPath path;
  Field surface0;  ///< initial indenter height (m)
  Field surface;   ///< current indenter height (m): changes only by wear
  std::unique_ptr<HalfSpace> half_space;
  std::unique_ptr<NormalSolver> normal;
  /// The Ciavarella–Jäger corrective problem's normal solver (solver.monotone = shortcut;
  /// null otherwise): preconditioned by its stick zone, and its displacement K p* kept apart
  /// from the normal solution's.
  std::unique_ptr<NormalSolver> corrective;
  std::unique_ptr<TangentialOperator> tangential_operator;
  std::unique_ptr<TangentialSolver> tangential;
  std::unique_ptr<StiffnessSolver> stiffness;  ///< null when solver.stiffness = none
  std::unique_ptr<WearModel> wear;             ///< null when wear.law = none
  /// Identity of this run's outputs (result.h5 /run_id and the checkpoint's run_id): set
  /// when a run starts, kept by a resume, so outputs of different runs are never mixed.
  std::string run_id;
  std::unique_ptr<FrictionLaw> friction;  ///< the Coulomb bound of every node
  /// Whether tangential increments try the same step of the previous cycle as their start
  /// (solver.predictor resolved by use_cycle_predictor).
  bool cycle_predictor = false;
};

/// Whether the step with this index and turning flag reports kx (solver.stiffness): every
/// step, or (turning) the ends of monotone segments — step 0, turning points and the path's
/// last step, which the paths flag as turning.
bool stiffness_wanted(const Model& model, int step, bool turning);
/// Everything a run does before it allocates the operators: the memory guard, the load path
/// (tables read), the surface (files read), the wear law and the pre-flight checks
/// (preflight.hpp). `fretbem check` stops here; build_model goes on from here.
std::unique_ptr<Model> prepare_model(const Scenario& sc);
/// prepare_model, then the half-space operator and the solvers.
/// Builds the surface and operators. The tangential operator is one-component (no y-solve)
/// when the coupling is the analogy and the path is collinear. With a distributed `comm` the
/// half-space and the solvers work on this rank's slab of the grid (docs/mpi-grid.md); the
/// surfaces stay whole on every rank (inputs, as the scenario), and what is not distributed
/// yet is refused (InputError naming the key).
std::unique_ptr<Model> build_model(const Scenario& sc,
                                   const Communicator& comm = serial_communicator());
/// solver.predictor resolved: cycle and none as said; auto: cycle when some transition of the
/// path's load occurs again later (a periodic path) and the run's memory estimate with the
/// predictor's memory (estimate_memory, cost_estimate.hpp) still fits in the usable memory.
bool use_cycle_predictor(const Scenario& sc, const LoadPath& path);
/// Throws InputError (one line) when the memory estimate (estimate_memory, with the cycle
/// predictor as resolved) exceeds the memory this process may use (the smaller of physical
/// memory and its cgroup limit, core/resources.hpp): a grid that cannot fit is refused before
/// anything large is allocated. prepare_model calls it.
void check_memory(const Scenario& sc, const LoadPath& path, bool cycle_predictor);
/// FFT threads: one below n = 512 whatever solver.threads asks (threads cost more than they
/// save on small grids); from there solver.threads, all usable CPUs (usable_cpus) for 0.
int fft_threads(const SolverSpec& solver, const Grid& grid);
/// The FFT settings of a scenario's HalfSpace: threads (fft_threads), precision, and
/// solver.fft_plan resolved (auto: measure when fft_wisdom::persistent).
FftOptions fft_options(const Scenario& sc);
/// The surface a scenario describes (generated, or loaded and checked against the grid).
Field make_surface(const Scenario& sc);

}  // namespace fretbem
