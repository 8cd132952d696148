// Per-increment bookkeeping that the projected and the partition solver share: the feasible
// start, the force redistribution, the slip-node step and the final report. Internal to
// src/contact.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "node_sets.hpp"

namespace fretbem::tangential_detail {

/// The nodes shift_to_force moves: the stick set, every contact node (into its disc where the
/// shift takes it there), or every contact node kept on its bound (turned, not projected: the
/// contact slides throughout and stays sliding).
enum class Movable { stick, all, on_bound };

/// Outcome of shift_to_force: remaining force mismatch (Pa * cells), the common shift, and
/// whether no moved node reached its bound (then tau changed by exactly lambda on every node).
struct ForceShift {
  double mismatch = 0.0;
  Eigen::VectorXd lambda;
  bool uniform = false;
};

/// C 1_S of a stick set S, kept for the uniform force corrections under the analogy
/// (restore_force, the slip-node step) and updated by sparse sums when S changes by few nodes.
struct StickImage {
  std::vector<std::uint8_t> stick;  ///< per contact node: the set imaged (empty: none yet)
  Field image;                      ///< C 1_S on the grid (m/Pa)
};

/// Buffers of the slip-node step, reused across iterations (the step and its image are zero
/// between uses).
struct SlipStepBuffers {
  VecField step, image;
  /// Nodes moved by the step and their traction change per component.
  std::vector<Eigen::Index> idx;
  std::vector<std::vector<double>> val;
  /// Slip nodes put back on their bound after a damped turn, and their traction change.
  std::vector<Eigen::Index> back_idx;
  std::vector<std::vector<double>> back_val;
};

/// Per-increment bookkeeping shared by the algorithms: start-up, force redistribution, the
/// slip-node step, the final report.
struct Workspace {
  Workspace(TangentialOperator& op, const TangentialIncrement& inc, TangentialOptions opt,
            BoundCache& cache);
  /// Makes the warm start feasible (and of the right force under force control), with u = C tau;
  /// takes inc.guess instead when it solves the increment within the tolerance or its QP
  /// energy is lower.
  void start(VecField& tau, VecField& u);
  void start_force(VecField& tau, VecField& u);
  /// inc.guess made feasible (of the target force under force control) in tg, with ug = C tg;
  /// false when it cannot be.
  bool feasible_guess(VecField& tg, VecField& ug);
  /// QP objective of the increment, 1/2 dtau . C dtau - dU . sum dtau (per cell area).
  double energy(const VecField& t, const VecField& w) const;
  /// Coulomb residual of (tau, u); classifies `sets`, sets result.shift.
  double residual(const VecField& tau, const VecField& u, double& stick_slip2);
  /// Line-searched local step of the slip nodes; true when the stick set changed. Under force
  /// control with `carry_force` the stick nodes take the step's force change within the same
  /// line search (the projected method); the partition method, which re-solves the stick set
  /// exactly at the force after every step, passes false.
  /// With `feasible` the step is cut where the first stick node's share of the force
  /// correction reaches its bound (no node leaves its disc, the force stays exact).
  bool slip_node_step(VecField& tau, VecField& u, bool carry_force = true, bool feasible = false);
  /// Uniform shift of the stick nodes' traction that restores the imposed total force; u is
  /// then updated. No-op under displacement control.
  void restore_force(VecField& tau, VecField& u);
  /// tau_i <- P_i(tau_i + lambda) on the `movable` contact nodes (under Movable::on_bound
  /// g_i (tau_i + lambda) / |tau_i + lambda|) with the lambda that brings the total (in
  /// Pa * cells) closest to `want`.
  ForceShift shift_to_force(Movable movable, const Eigen::VectorXd& want, VecField& tau) const;
  /// Brings stick_image up to the current stick set.
  void update_stick_image();
  /// Fills the report; throws SolverError when the increment did not converge.
  TangentialResult finish(const VecField& tau, const std::string& algorithm);
  /// The grid's reduction layer: every sum over nodes goes through it.
  const Communicator& comm() const { return op.half_space().communicator(); }

  TangentialOperator& op;
  const TangentialIncrement& inc;
  TangentialOptions opt;
  std::int64_t conv0 = 0;  ///< the operator's convolutions before the increment
  NodeSets sets;
  double scale = 1.0, gsum = 0.0;  ///< |C g| and sum g (Pa * cells)
  StickImage stick_image;
  SlipStepBuffers slip;
  bool exact = false;  ///< u was set to C tau by one product at the start (no drift yet)
  /// The algorithm reads u on the contact nodes only until its last product (the projected
  /// one): restore_force then updates u there only.
  bool u_on_contact_only = false;
  /// The residual and stick-node slip sum start() computed for the start it took (a guess that
  /// met the tolerance), with `sets` and result.shift still those of that start; the solver's
  /// first residual reads it instead of computing it again. Empty otherwise.
  std::optional<std::pair<double, double>> start_residual;
  TangentialResult result;
};

}  // namespace fretbem::tangential_detail
