// Internal helpers shared by the tangential algorithms (not part of the public API).
#pragma once

#include <string>

#include "fretbem/tangential_solver.hpp"

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
/// Projects every node onto its disc |tau| <= g (open nodes to zero); true if anything moved.
bool project_all(const Field& g, VecField& tau);

/// Displacement scale |C g| (rms over contact), recomputed only when the bound changes.
class ScaleCache {
 public:
  double get(TangentialOperator& op, const Field& g);

 private:
  Field g_;
  double scale_ = 1.0;
};

/// Per-increment bookkeeping shared by the algorithms: start-up, force redistribution,
/// the final report.
struct Workspace {
  Workspace(TangentialOperator& op, const TangentialIncrement& inc, TangentialOptions opt,
            ScaleCache& cache);
  /// Makes the warm start feasible (and of the right force under force control), with u = C tau.
  void start(VecField& tau, VecField& u);
  void start_force(VecField& tau, VecField& u);
  /// After a CG step on the stick set `free`: projects stick nodes that left their disc, moves
  /// slip nodes by a Jacobi step along their slip, redistributes the force error (force
  /// control), updates u. Returns true when the stick set changed.
  bool project_and_reenter(const Field& free, VecField& tau, VecField& u);
  /// Line-searched local step of the slip nodes; true when a node re-entered its disc.
  bool slip_node_step(const Field& free, VecField& tau, VecField& u);
  /// Uniform shift of the stick nodes' traction that restores the imposed total force; u is
  /// then recomputed. No-op under displacement control.
  void restore_force(VecField& tau, VecField& u);
  /// tau_i <- P_i(tau_i + lambda) on the movable nodes with the lambda that brings the total
  /// (in Pa * cells) closest to `want`; returns the remaining mismatch.
  bool add_uniform_shift(const Field& stick, const VecField& before, const VecField& tau,
                         VecField& u);
  double shift_to_force(const Field& movable, const Eigen::VectorXd& want, VecField& tau) const;
  /// Fills the report; throws SolverError when the increment did not converge.
  TangentialResult finish(const VecField& tau, const std::string& algorithm);

  TangentialOperator& op;
  const TangentialIncrement& inc;
  TangentialOptions opt;
  double scale = 1.0;
  bool dirty = false;
  Field stick_mask, stick_image;  ///< S and C 1_S of the last uniform force correction  ///< u lags
                                  ///< tau by second-order terms: recompute before trusting it
  std::int64_t conv0 = 0;
  TangentialResult result;
};

}  // namespace fretbem::tangential_detail
