// TangentialSolver: one load increment of the frictional (Coulomb) tangential contact at fixed
// pressure, as the strictly convex QP of docs/algorithms.md:
//   min_tau 1/2 (tau - tau0)^T C (tau - tau0) - (tau - tau0) . dU   s.t. |tau_i| <= g_i,
// g_i = mu p_i. Its optimality conditions are Coulomb's law for the slip increment
// s_i = dU - (u_i - u0_i): stick (s_i = 0, |tau_i| <= g_i) or slip (|tau_i| = g_i, tau_i || s_i).
// Displacement control imposes dU; force control imposes sum tau h^2 = F and dU is the
// multiplier.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>

#include "fretbem/contact/normal_solver.hpp"
#include "fretbem/contact/preconditioning.hpp"
#include "fretbem/contact/tangential_operator.hpp"

namespace fretbem {

namespace tangential_detail {
class BoundCache;
}  // namespace tangential_detail

enum class TangentialControl { displacement, force };

struct TangentialOptions {
  double tolerance = 1e-10;  ///< relative slip residual at which an increment stops
  int max_iterations = 5000;
  /// Fourier preconditioning of the projected CG's stick-set directions,
  /// z = S K_z^-1 S s (S the stick set), as in the normal solver; see ProjectedCgSolver.
  Precondition precondition = Precondition::automatic;
};

/// One increment: the state at the end of the previous step and the load of this one.
struct TangentialIncrement {
  const Field* bound = nullptr;    ///< g = mu p (Pa); 0 marks open nodes
  const VecField* tau0 = nullptr;  ///< traction at the end of the previous step (Pa)
  const VecField* u0 = nullptr;    ///< C tau0 (m)
  TangentialControl control = TangentialControl::displacement;
  Eigen::VectorXd target;  ///< dU (m) or total force F (N), operator components
  /// Optional predictor of the solution (Pa), e.g. the same step of the previous load cycle:
  /// projected onto the discs and the force, it replaces the start when its QP energy is lower.
  /// It changes only where the iteration starts, never the converged answer's tolerance.
  const VecField* guess = nullptr;
  /// The guess continues the solved branch to second order in the load step (the Masing
  /// image, a secant): taken as the start whenever it is feasible, without building and
  /// imaging the force-shifted starts it would otherwise be compared against (two products).
  bool guess_continues = false;
  /// The caller reads u on the contact nodes of `bound` only until it images a traction again
  /// (every later increment has this contact: one normal load, no wear). The projected solver
  /// then stops on its incrementally updated u without the verifying product that refreshes u
  /// elsewhere: u on contact is C tau to the round-off of its updates (see
  /// ProjectedCgSolver::kUnverifiedTolerance), and the cells off contact keep their last
  /// exact values.
  bool contact_fixed = false;
};

/// Convergence report of one increment. residual: rms over contact nodes of the violation of
/// Coulomb's law in displacement units (slip of stick nodes; slip not parallel to the traction
/// at slip nodes), relative to the displacement scale |C g|.
struct TangentialResult {
  int iterations = 0;
  double residual = 0.0;
  bool converged = false;
  int convolutions = 0;
  Eigen::VectorXd shift;  ///< rigid shift increment dU (m)
  Eigen::VectorXd force;  ///< total traction sum tau h^2 (N)
};

/// Interface of the incremental algorithms; both report iterations and residual and throw
/// SolverError when an increment does not converge.
class TangentialSolver {
 public:
  virtual ~TangentialSolver() = default;
  /// Solves one increment; tau and u hold the warm start on entry (e.g. tau0, u0), the
  /// solution on exit.
  virtual TangentialResult solve(const TangentialIncrement& inc, VecField& tau, VecField& u) = 0;
};

/// Polonsky–Keer-type projected conjugate gradient: CG on the stick set, projection of
/// tractions onto their Coulomb discs, Jacobi re-entry of slip nodes whose slip turned,
/// conjugacy restarted whenever the stick set changes. About one convolution per iteration,
/// plus one per component when preconditioned.
class ProjectedCgSolver final : public TangentialSolver {
 public:
  /// Throws InputError when opt.tolerance is below the operator's min_tolerance() (float FFTs).
  ProjectedCgSolver(TangentialOperator& op, TangentialOptions opt);
  ~ProjectedCgSolver() override;
  TangentialResult solve(const TangentialIncrement& inc, VecField& tau, VecField& u) override;
  /// Whether solve() preconditions an increment with this bound (TangentialOptions::
  /// precondition; automatic: PreconditionDecision::for_set of the contact nodes).
  bool preconditioned(const Field& bound) const;
  /// Automatic preconditioning from this largest contact patch (PreconditionDecision).
  static constexpr std::int64_t kPatchNodes = PreconditionDecision::kPatchNodes;
  /// Smallest tolerance at which an increment with contact_fixed ends without the verifying
  /// product (double-precision FFTs only): each update of the incremental u carries the
  /// product's round-off, ~1e-15 of its size (log2 of the padded size times the unit
  /// round-off), and the updates sum to about the start's distance from the solution, so the
  /// drift of the residual stays three decades below this.
  static constexpr double kUnverifiedTolerance = 1e-11;

 private:
  template <int NC>
  class Iteration;  // the CG problem of one increment (tangential_solver.cpp)
  template <int NC>
  TangentialResult solve_components(const TangentialIncrement& inc, VecField& tau, VecField& u);

  TangentialOperator& op_;
  TangentialOptions opt_;
  PreconditionDecision preconditioning_;  // remembers the flood fill of the last contact set
  VecField d_, q_, r_, z_;  // direction, its image C d; preconditioner input S s, output
  // What the increments need of the bound (contact nodes, sum g, |C g|), kept while it holds.
  std::unique_ptr<tangential_detail::BoundCache> cache_;
};

/// The paper's fixed-point partition iteration (Methods): fix the stick/slip partition, set
/// slip tractions to the bound along the slip direction, solve the stick nodes exactly by CG,
/// move violators across, repeat. The baseline the projected method is measured against.
class PartitionSolver final : public TangentialSolver {
 public:
  /// Throws InputError when opt.tolerance is below the operator's min_tolerance() (float FFTs).
  PartitionSolver(TangentialOperator& op, TangentialOptions opt);
  ~PartitionSolver() override;
  TangentialResult solve(const TangentialIncrement& inc, VecField& tau, VecField& u) override;

 private:
  TangentialOperator& op_;
  TangentialOptions opt_;
  std::unique_ptr<tangential_detail::BoundCache> cache_;
};

/// Coulomb-law residual of a state (see TangentialResult::residual) and the slip increment s.
/// Under force control dU is the mean of u - u0 over stick nodes.
/// On a distributed grid the fields are this rank's slabs and the sums go through `comm`.
double coulomb_residual(const Grid& grid, const TangentialIncrement& inc, const VecField& tau,
                        const VecField& u, double scale, Eigen::VectorXd& dU, VecField& s,
                        const Communicator& comm = serial_communicator());

/// Stick-node tolerance: a node with |tau| < g (1 - kBoundEps) is free to stick; slip nodes sit
/// on the bound up to round-off because they are placed there by projection.
inline constexpr double kBoundEps = 1e-12;

}  // namespace fretbem

namespace fretbem {

/// The solver a run uses: the chosen algorithm first; when an increment does not converge,
/// fallbacks in order — the other algorithm from the same warm start; under force control,
/// displacement-controlled solves for the shift that carries the force; then the increment
/// split into 2, 4, ..., kMaxSubsteps equal sub-steps (each with both algorithms). It says so once
/// on stderr (per solver) and throws the first algorithm's SolverError only when every
/// fallback failed. Sub-steps follow the load linearly (force or rigid shift): on a monotone
/// segment at constant pressure the incremental solution does not depend on the step size.
class FallbackTangentialSolver final : public TangentialSolver {
 public:
  /// `tolerance`: the solvers' relative tolerance (the force fallback's force tolerance is
  /// tolerance * sum g h^2, as the force part of TangentialResult::residual).
  FallbackTangentialSolver(TangentialOperator& op, double tolerance,
                           std::unique_ptr<TangentialSolver> primary,
                           std::unique_ptr<TangentialSolver> secondary);
  TangentialResult solve(const TangentialIncrement& inc, VecField& tau, VecField& u) override;
  /// Fallbacks used so far (0 when every increment converged at once).
  int fallbacks() const { return fallbacks_; }
  static constexpr int kMaxSubsteps = 16;
  /// Broyden iterations of the force-control fallback.
  static constexpr int kShiftIterations = 60;

 private:
  bool try_solve(TangentialSolver& s, const TangentialIncrement& inc, VecField& tau, VecField& u,
                 TangentialResult& r);
  bool force_by_shift(const TangentialIncrement& inc, VecField& tau, VecField& u,
                      TangentialResult& r);
  bool substeps(int m, const TangentialIncrement& inc, VecField& tau, VecField& u,
                TangentialResult& r);
  void announce(const std::string& what);

  Grid grid_;
  const Communicator& comm_;  // the grid's reduction layer
  double tolerance_, self_compliance_;
  std::unique_ptr<TangentialSolver> primary_, secondary_;
  int fallbacks_ = 0;
  bool announced_ = false;
};

}  // namespace fretbem
