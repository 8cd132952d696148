// The paper's partition iteration (Methods section), kept as the baseline algorithm.
#include <cmath>

#include "fretbem/contact/tangential_solver.hpp"
#include "tangential_detail.hpp"

namespace fretbem {

using namespace tangential_detail;

namespace {

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

// Moves nodes across the partition: stick nodes over their bound start to slip, slip nodes
// slipping against their traction stick again. Slip tractions are put on the bound along the
// current slip direction. Returns the number of nodes moved.
int repartition(const TangentialIncrement& inc, const VecField& u, Field& stick, VecField& tau) {
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
    } else if (s.dot(t) < 0.0) {
      stick(k) = 1.0, ++moved;  // slipping backwards: it sticks
      continue;
    } else if (s.norm() > 0.0) {
      t = g(k) * s.normalized();  // bound along the slip direction
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
  int used = 0;
  while (used < opt_.max_iterations) {
    used += solve_stick_set(op_, inc, stick, opt_.tolerance * w.scale, opt_.max_iterations - used,
                            tau, u);
    const int moved = repartition(inc, u, stick, tau);
    op_.apply(tau, u), ++used;
    w.restore_force(tau, u);
    w.result.residual = coulomb_residual(op_.grid(), inc, tau, u, w.scale, w.result.shift, s);
    if (moved == 0 && w.result.residual <= opt_.tolerance) {
      w.result.converged = true;
      break;
    }
  }
  w.result.iterations = used;
  return w.finish(tau, "partition");
}

}  // namespace fretbem
