// WearPreconditioner: exact solve of the frozen-slip Newton matrix of the wear ODE (see the
// header for the derivation).
#include "fretbem/wear/preconditioner.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "fretbem/core/errors.hpp"

namespace fretbem {

WearPreconditioner::WearPreconditioner(HalfSpace& half_space, bool force_control, double tolerance)
    : hs_(half_space), force_control_(force_control), tol_(tolerance) {}

void WearPreconditioner::setup(const Field& pressure, const Field& wear_per_cycle) {
  mask_ = (pressure > 0.0).cast<double>();
  d_ = mask_ * (wear_per_cycle / pressure.max(1e-300)).max(0.0);
  cached_gamma_ = -1.0;
  ready_ = comm().any((mask_ > 0.0).any());
}

void WearPreconditioner::solve(const Field& b, double gamma, Field& x, double residual) {
  if (!ready_) {
    x = b;
    return;
  }
  Field& q = q_;
  const Field rhs = -(b * mask_);
  const double norm = std::sqrt(comm().sum((rhs * rhs).sum()));
  // The residual allowed as a share of |b_A|; the response to 1 is solved to the same share
  // (its multiplier scales it to about |b_A|: for b_A = beta 1 it is exactly -beta).
  const double share = norm > 0.0 ? residual / norm : 0.0;
  cg(rhs, gamma, q, share);
  if (force_control_) {
    // The rigid approach d_delta keeps the normal force: sum q = 0 (superposition of the
    // response to -b and to a unit approach on A).
    if (gamma != cached_gamma_ || std::max(tol_, share) < cached_share_) {
      cg(mask_, gamma, ones_solution_, share);
      cached_gamma_ = gamma;
      cached_share_ = std::max(tol_, share);
    }
    double sums[2] = {q.sum(), ones_solution_.sum()};
    comm().sum(sums);
    q -= (sums[0] / sums[1]) * ones_solution_;
  }
  x = b + gamma * d_ * q;
}

// Jacobi-preconditioned CG for (C_A + gamma D) q = r on A. The operator is SPD on A: C is (the
// Boussinesq influence matrix), gamma D >= 0.
void WearPreconditioner::cg(const Field& r, double gamma, Field& q, double share) {
  diag_ = mask_ * (hs_.normal_self() + gamma * d_) + (1.0 - mask_);
  q.setZero(r.rows(), r.cols());
  r_ = r * mask_;
  const double r0 = std::sqrt(comm().sum((r_ * r_).sum()));
  if (r0 == 0.0) return;
  const double stop = std::max(tol_, share) * r0;
  z_ = r_ / diag_;
  s_ = z_;
  double rz = comm().sum((r_ * z_).sum());
  for (int it = 0; it < 1000; ++it) {
    hs_.normal(s_, u_);
    t_ = mask_ * (u_ + gamma * d_ * s_);
    const double alpha = rz / comm().sum((s_ * t_).sum());
    q += alpha * s_;
    r_ -= alpha * t_;
    ++iterations_;
    z_ = r_ / diag_;
    double sums[2] = {(r_ * r_).sum(), (r_ * z_).sum()};  // one message per iteration
    comm().sum(sums);
    if (std::sqrt(sums[0]) <= stop) return;
    const double rz_new = sums[1];
    s_ = z_ + (rz_new / rz) * s_;
    rz = rz_new;
  }
  throw SolverError("wear preconditioner: inner CG not converged in 1000 iterations");
}

}  // namespace fretbem
