// Internal helpers shared by the tangential algorithms (not part of the public API).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "fretbem/contact/tangential_solver.hpp"

namespace fretbem::tangential_detail {

/// |tau| per node.
Field magnitude(const VecField& tau);
/// 1 where a node is in contact and strictly inside its Coulomb disc (free to stick), else 0.
Field free_mask(const Field& g, const Field& mag);
/// Total force sum tau h^2 per component (N).
Eigen::VectorXd total_force(const VecField& tau, const Grid& grid);
/// Largest attainable tangential force sum g h^2 (N).
double bound_force(const Field& g, const Grid& grid);
/// dU: imposed (displacement control) or the mean of u - u0 over stick nodes (force control).
Eigen::VectorXd shift_estimate(const TangentialIncrement& inc, const VecField& u,
                               const Field& free);
/// Force control at or past full sliding: |F| >= sum g h^2 (1 - tolerance).
bool past_full_sliding(const TangentialIncrement& inc, const Grid& grid, double tolerance);
/// Projects every node onto its disc |tau| <= g (open nodes to zero); true if anything moved.
bool project_all(const Field& g, VecField& tau);

/// The contact nodes of one increment (g > 0, fixed while the pressure is) and which of them
/// stick. Every per-iteration pass of the projected solver runs over this list instead of the
/// whole grid: off contact tau = 0 and nothing is read (u there is only refreshed by the exact
/// products).
struct NodeSets {
  explicit NodeSets(const Field& g);
  /// Marks the contact nodes strictly inside their disc as stick; returns how many.
  std::int64_t classify(const Field& g, const VecField& tau);

  std::vector<Eigen::Index> contact;  ///< grid index of each contact node
  std::vector<std::uint8_t> stick;    ///< per contact node: 1 stick, 0 slip
  std::int64_t nstick = 0;
};

/// Coulomb residual (see TangentialResult::residual) over the contact nodes; classifies the
/// stick set first and returns dU and the squared stick slip sum_S |s|^2 (the CG gradient norm).
double residual(NodeSets& sets, const TangentialIncrement& inc, const VecField& tau,
                const VecField& u, double scale, const Grid& grid, Eigen::VectorXd& dU,
                double& stick_slip2);

/// Displacement scale |C g| (rms over contact), recomputed only when the bound changes.
class ScaleCache {
 public:
  double get(TangentialOperator& op, const Field& g);

 private:
  Field g_;
  double scale_ = 1.0;
};

/// Outcome of shift_to_force: remaining force mismatch (Pa * cells), the common shift, and
/// whether no moved node reached its bound (then tau changed by exactly lambda on every node).
struct ForceShift {
  double mismatch = 0.0;
  Eigen::VectorXd lambda;
  bool uniform = false;
};

/// Per-increment bookkeeping shared by the algorithms: start-up, force redistribution,
/// the final report.
struct Workspace {
  Workspace(TangentialOperator& op, const TangentialIncrement& inc, TangentialOptions opt,
            ScaleCache& cache);
  /// Makes the warm start feasible (and of the right force under force control), with u = C tau.
  void start(VecField& tau, VecField& u);
  void start_force(VecField& tau, VecField& u);
  /// Takes inc.guess (made feasible) instead of tau when its QP energy is lower.
  void start_guess(VecField& tau, VecField& u);
  /// QP objective of the increment, 1/2 dtau . C dtau - dU . sum dtau (per cell area).
  double energy(const VecField& t, const VecField& w) const;
  /// Coulomb residual of (tau, u); classifies `sets`, sets result.shift.
  double residual(const VecField& tau, const VecField& u, double& stick_slip2);
  /// The CG step tau += alpha d, u += alpha q from the stick set `sets.stick` (still the set
  /// of the step), then: projects stick nodes that left their disc, moves slip nodes by a
  /// Jacobi step along their slip, redistributes the force error (force control). Returns true
  /// when the stick set changed.
  bool step_and_project(double alpha, const VecField& d, const VecField& q, VecField& tau,
                        VecField& u);
  /// Line-searched local step of the slip nodes; true when the stick set changed. Under force
  /// control with `carry_force` the stick nodes take the step's force change within the same
  /// line search (the projected method); the partition method, which re-solves the stick set
  /// exactly at the force after every step, passes false.
  bool slip_node_step(VecField& tau, VecField& u, bool carry_force = true);
  /// Uniform shift of the stick nodes' traction that restores the imposed total force; u is
  /// then updated. No-op under displacement control.
  void restore_force(VecField& tau, VecField& u);
  /// tau_i <- P_i(tau_i + lambda) on the movable contact nodes (the stick set, or all when
  /// `all`) with the lambda that brings the total (in Pa * cells) closest to `want`.
  ForceShift shift_to_force(bool all, const Eigen::VectorXd& want, VecField& tau) const;
  /// Brings stick_image = C 1_S up to the current stick set.
  void update_stick_image();
  /// Fills the report; throws SolverError when the increment did not converge.
  TangentialResult finish(const VecField& tau, const std::string& algorithm);

  TangentialOperator& op;
  const TangentialIncrement& inc;
  TangentialOptions opt;
  NodeSets sets;
  double scale = 1.0, gsum = 0.0;  ///< |C g| and sum g (Pa * cells)
  /// Stick flags and C 1_S of the last uniform force correction.
  std::vector<std::uint8_t> image_stick;
  Field stick_image;
  /// Slip-node step and its image (zero between uses), reused across iterations.
  VecField slip_step, slip_image;
  std::vector<Eigen::Index> idx;
  std::vector<std::vector<double>> val;
  /// Slip nodes put back on their bound after a damped turn, and their traction change.
  std::vector<Eigen::Index> back_idx;
  std::vector<std::vector<double>> back_val;
  std::int64_t conv0 = 0;
  bool exact = false;  ///< u was set to C tau by one product at the start (no drift yet)
  TangentialResult result;
};

}  // namespace fretbem::tangential_detail
