// The paper's partition iteration (Methods section), kept as the baseline algorithm.
#include <cmath>
#include <limits>

#include "fretbem/contact/tangential_solver.hpp"
#include "tangential_detail.hpp"

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

// Moves nodes across the partition: stick nodes over their bound start to slip; slip nodes
// take the local Newton step y = tau + omega s (omega = 1 / C_ii, the node's own compliance:
// the exact update of that node with the others held) and stick again when it re-enters the
// disc, else stay on the bound along y. Setting the slip traction along s itself (the
// earlier rule) turned nodes with a vanishing slip in arbitrary directions; under Cerruti's
// x-y coupling four nodes cycled between stick and slip forever (issue 14, item 7).
// Returns the number of nodes moved.
int repartition(const TangentialIncrement& inc, const VecField& u, double omega, Field& stick,
                VecField& tau) {
  const Field& g = *inc.bound;
  const int nc = int(tau.size());
  const Eigen::VectorXd dU = shift_estimate(inc, u, stick);
  const Field mag = magnitude(tau);
  int moved = 0;
  Eigen::VectorXd s(nc), t(nc);
  for (Eigen::Index k = 0; k < g.size(); ++k) {
    if (!(g(k) > 0.0)) continue;
    for (int c = 0; c < nc; ++c) s(c) = dU(c) - (u[c](k) - (*inc.u0)[c](k)), t(c) = tau[c](k);
    if (stick(k) > 0.0) {
      if (mag(k) <= g(k)) continue;
      stick(k) = 0.0, ++moved;
      t *= g(k) / mag(k);
    } else {
      t += omega * s;
      const double m = t.norm();
      if (m < g(k) * (1.0 - kBoundEps))
        stick(k) = 1.0, ++moved;  // slipping backwards: it sticks
      else
        t *= g(k) / m;  // on the bound along the local solution
    }
    for (int c = 0; c < nc; ++c) tau[c](k) = t(c);
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
    const int moved = repartition(inc, u, 1.0 / op_.self_compliance(), stick, tau);
    op_.apply(tau, u), ++used;
    w.restore_force(tau, u);
    w.result.residual = coulomb_residual(op_.grid(), inc, tau, u, w.scale, w.result.shift, s);
    if (moved == 0 && w.result.residual <= opt_.tolerance) {
      w.result.converged = true;
      break;
    }
    // A partition that cycles (the same few nodes in and out, measured under Cerruti's
    // coupling: residual ~0.25 for 5000 iterations) does not come back: stop and report, so
    // that FallbackTangentialSolver hands the increment to the projected method at once.
    if (w.result.residual < 0.5 * best) best = w.result.residual, best_outer = outer;
    if (++outer - best_outer > kStagnantPartitions) break;
  }
  w.result.iterations = used;
  return w.finish(tau, "partition");
}

}  // namespace fretbem
