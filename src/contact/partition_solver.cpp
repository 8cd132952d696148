// The paper's partition iteration (Methods section), kept as the baseline algorithm.
#include <cmath>
#include <limits>

#include "fretbem/contact/tangential_solver.hpp"
#include "workspace.hpp"

namespace fretbem {

using namespace tangential_detail;

namespace {

// Outer iterations without halving the best residual after which the partition is cycling.
constexpr int kStagnantPartitions = 30;

// Conjugate gradients for s = 0 on the stick set with the slip tractions held fixed
// (under force control with the total force held: zero-mean directions). Returns iterations.
int solve_stick_set(TangentialOperator& op, const TangentialIncrement& inc, const Field& stick,
                    double tol_abs, int max_it, VecField& tau, VecField& u) {
  const int nc = op.components();
  VecField s(nc), d = op.zeros(), q;
  double rr_old = 0.0;
  for (int it = 0; it < max_it; ++it) {
    const Eigen::VectorXd dU = shift_estimate(inc, u, stick);
    double rr = 0.0;
    for (int c = 0; c < nc; ++c) {
      s[c] = stick * (dU(c) - (u[c] - (*inc.u0)[c]));
      rr += s[c].square().sum();
    }
    if (std::sqrt(rr / std::max(1.0, stick.sum())) <= tol_abs) return it;
    const double beta = it == 0 ? 0.0 : rr / rr_old;
    rr_old = rr;
    for (int c = 0; c < nc; ++c) d[c] = s[c] + beta * d[c];
    op.apply(d, q);
    double den = 0.0;
    for (int c = 0; c < nc; ++c) {
      const double qbar =
          inc.control == TangentialControl::force ? (stick * q[c]).sum() / stick.sum() : 0.0;
      den += (stick * (q[c] - qbar) * d[c]).sum();
    }
    if (!(den > 0.0)) return it;
    const double alpha = rr / den;
    for (int c = 0; c < nc; ++c) tau[c] += alpha * d[c], u[c] += alpha * q[c];
  }
  return max_it;
}

// Moves nodes across the partition. Slip nodes first, by the projected method's slip-node
// step (Workspace::slip_node_step): the local Newton step y = P(tau + s / C_ii) of every slip
// node with an exact line search on the QP; nodes that re-enter their disc stick again. Then
// stick nodes over their bound start to slip, projected radially onto it. Returns the number
// of nodes moved.
//
// The line search keeps the partition from cycling under Cerruti's x-y coupling: an undamped
// simultaneous step tau + s / C_ii would be a Jacobi iteration on the slip directions, and Jacobi
// on the dense Boussinesq/Cerruti kernel overshoots every smooth mode (the off-diagonal row sum
// over a slip ring exceeds C_ii many times). Under the analogy at 0 degrees a slip direction is a
// sign, so the overshoot is cut off by the bound and harmless; under Cerruti the y-traction of the
// slip ring rotates, the overshoot swings it from side to side, and nodes whose slip swings
// backwards fall in and out of the stick set (measured: 4-7 nodes cycling, residual ~0.25 for 5000
// iterations).
int repartition(Workspace& w, Field& stick, VecField& tau, VecField& u) {
  const Field& g = *w.inc.bound;
  NodeSets& sets = w.sets;
  sets.nstick = 0;
  for (std::size_t j = 0; j < sets.contact.size(); ++j)
    sets.stick[j] = stick(sets.contact[j]) > 0.0, sets.nstick += sets.stick[j];
  w.slip_node_step(tau, u, false);  // the stick solve that follows restores the force
  const int nc = int(tau.size());
  int moved = 0;
  for (std::size_t j = 0; j < sets.contact.size(); ++j) {
    const Eigen::Index k = sets.contact[j];
    double m2 = 0.0;
    for (int c = 0; c < nc; ++c) m2 += tau[c](k) * tau[c](k);
    const double m = std::sqrt(m2);
    if (sets.stick[j]) {
      if (m <= g(k)) continue;
      stick(k) = 0.0, ++moved;  // over its bound: it slips
      for (int c = 0; c < nc; ++c) tau[c](k) *= g(k) / m;
    } else if (m < g(k) * (1.0 - kBoundEps)) {
      stick(k) = 1.0, ++moved;  // slipping backwards: re-entered its disc, it sticks
    }
  }
  return moved;
}

}  // namespace

PartitionSolver::PartitionSolver(TangentialOperator& op, TangentialOptions opt)
    : op_(op), opt_(opt), cache_(std::make_unique<ScaleCache>()) {
  op_.half_space().require_tolerance(opt_.tolerance, "tangential solver");
}

PartitionSolver::~PartitionSolver() = default;

TangentialResult PartitionSolver::solve(const TangentialIncrement& inc, VecField& tau,
                                        VecField& u) {
  Workspace w(op_, inc, opt_, *cache_);
  w.start(tau, u);
  Field stick = free_mask(*inc.bound, magnitude(tau));
  VecField s;
  int used = 0, outer = 0, best_outer = 0;
  double best = std::numeric_limits<double>::infinity();
  while (used < opt_.max_iterations) {
    used += solve_stick_set(op_, inc, stick, opt_.tolerance * w.scale, opt_.max_iterations - used,
                            tau, u);
    const int moved = repartition(w, stick, tau, u);
    op_.apply(tau, u), ++used;
    w.restore_force(tau, u);
    w.result.residual = coulomb_residual(op_.grid(), inc, tau, u, w.scale, w.result.shift, s);
    if (moved == 0 && w.result.residual <= opt_.tolerance) {
      w.result.converged = true;
      break;
    }
    // A partition that cycles does not come back: stop and report, so that
    // FallbackTangentialSolver hands the increment to the projected method at once (a safety
    // net: the Cerruti cycling that needed it is fixed in repartition).
    if (w.result.residual < 0.5 * best) best = w.result.residual, best_outer = outer;
    if (++outer - best_outer > kStagnantPartitions) break;
  }
  w.result.iterations = used;
  return w.finish(tau, "partition");
}

}  // namespace fretbem
