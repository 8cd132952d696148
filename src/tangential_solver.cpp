#include "fretbem/tangential_solver.hpp"

#include <cmath>

#include "tangential_detail.hpp"

namespace fretbem {

using namespace tangential_detail;

double coulomb_residual(const Grid& grid, const TangentialIncrement& inc, const VecField& tau,
                        const VecField& u, double scale, Eigen::VectorXd& dU, VecField& s) {
  const Field& g = *inc.bound;
  const int nc = int(tau.size());
  const Field mag = magnitude(tau);
  const Field free = free_mask(g, mag);
  const Field contact = (g > 0.0).cast<double>();
  dU = shift_estimate(inc, u, free);
  s.resize(nc);
  for (int c = 0; c < nc; ++c) s[c] = dU(c) - (u[c] - (*inc.u0)[c]);
  // Stick nodes must not slip; slip nodes may slip only outward along their traction.
  Field along = Field::Zero(g.rows(), g.cols());
  for (int c = 0; c < nc; ++c) along += s[c] * tau[c];
  along = (mag > 0.0).select(along / mag, 0.0).max(0.0);
  Field viol = Field::Zero(g.rows(), g.cols());
  for (int c = 0; c < nc; ++c) {
    const Field unit = (mag > 0.0).select(tau[c] / mag, 0.0);
    viol += contact * (free * s[c].square() + (1.0 - free) * (s[c] - along * unit).square());
  }
  double res = std::sqrt(viol.sum() / std::max(1.0, contact.sum())) / scale;
  if (inc.control == TangentialControl::force) {
    // Force mismatch relative to the full-sliding force sum g h^2.
    const double fmax = bound_force(g, grid);
    res = std::max(res, (total_force(tau, grid) - inc.target).norm() / fmax);
  }
  return res;
}

ProjectedCgSolver::ProjectedCgSolver(TangentialOperator& op, TangentialOptions opt)
    : op_(op), opt_(opt), cache_(std::make_unique<ScaleCache>()) {}

ProjectedCgSolver::~ProjectedCgSolver() = default;

TangentialResult ProjectedCgSolver::solve(const TangentialIncrement& inc, VecField& tau,
                                          VecField& u) {
  const int nc = op_.components();
  Workspace w(op_, inc, opt_, *cache_);
  w.start(tau, u);
  bool restart = true, verified = false;
  double g_old = 1.0;
  for (int it = 0;; ++it) {
    w.result.iterations = it;
    if (w.dirty && it % 8 == 0) op_.apply(tau, u), w.dirty = false;
    w.result.residual = coulomb_residual(op_.grid(), inc, tau, u, w.scale, w.result.shift, s_);
    if (w.result.residual <= opt_.tolerance) {
      if (verified) {
        w.result.converged = true;
        break;
      }
      op_.apply(tau, u);  // drop round-off of the incremental updates, then check again
      verified = true;
      continue;
    }
    verified = false;
    if (it >= opt_.max_iterations) break;
    const Field free = free_mask(*inc.bound, magnitude(tau));
    // CG on the stick set. The QP's gradient is -s; under force control s has zero mean on
    // the stick set (dU is that mean), so the directions keep the total force.
    double G = 0.0;
    for (int c = 0; c < nc; ++c) G += (free * s_[c].square()).sum();
    const double beta = restart ? 0.0 : G / g_old;
    g_old = G;
    if (restart) d_ = op_.zeros();
    for (int c = 0; c < nc; ++c) d_[c] = free * (s_[c] + beta * d_[c]);
    double alpha = 0.0;
    if (G > 0.0) {
      op_.apply(d_, q_);
      double num = 0.0, den = 0.0;
      for (int c = 0; c < nc; ++c) {
        const double qbar =
            inc.control == TangentialControl::force ? (free * q_[c]).sum() / free.sum() : 0.0;
        num += (free * s_[c] * d_[c]).sum();
        den += (free * (q_[c] - qbar) * d_[c]).sum();
      }
      if (den > 0.0) alpha = num / den;
      for (int c = 0; c < nc; ++c) tau[c] += alpha * d_[c], u[c] += alpha * q_[c];
    }
    restart = w.project_and_reenter(free, tau, u) || !(alpha > 0.0);
  }
  return w.finish(tau, "projected-CG");
}

}  // namespace fretbem
