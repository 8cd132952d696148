#include "fretbem/contact/stiffness.hpp"

#include <cmath>
#include <sstream>

#include "fretbem/core/errors.hpp"

namespace fretbem {

StiffnessSolver::StiffnessSolver(TangentialOperator& op, double tolerance, int max_iterations)
    : op_(op), tol_(tolerance), max_it_(max_iterations) {
  op_.half_space().require_tolerance(tol_, "stiffness solver");
}

StiffnessResult StiffnessSolver::solve(const StateField& state) {
  const int nc = op_.components();
  const Field stick = (state == std::uint8_t(NodeState::stick)).cast<double>();
  StiffnessResult res;
  const double nstick = stick.sum();
  if (nstick == 0.0) return res;  // full sliding: no stiffness
  // k_x depends on the stick set alone: an unchanged set (a skipped step, a steady stretch)
  // needs no new solve.
  if (last_stick_.size() == stick.size() && (last_stick_ == stick).all()) {
    res.kx = last_kx_;
    return res;
  }
  if (psi_.size() != std::size_t(nc)) psi_ = op_.zeros();
  for (auto& p : psi_) p *= stick;
  op_.apply(psi_, u_);
  // Unit shift along x: component 0 in both the 1-D (analogy, decoupled) and 2-D bases.
  r_.resize(nc);
  double rr = 0.0, rr_old = 1.0;
  const double bnorm = std::sqrt(nstick);
  d_ = op_.zeros();
  for (int it = 0;; ++it) {
    rr = 0.0;
    for (int c = 0; c < nc; ++c) {
      r_[c] = stick * ((c == 0 ? 1.0 : 0.0) - u_[c]);
      rr += r_[c].square().sum();
    }
    res.iterations = it;
    res.residual = std::sqrt(rr) / bnorm;
    if (res.residual <= tol_ || it >= max_it_) break;
    const double beta = it == 0 ? 0.0 : rr / rr_old;
    rr_old = rr;
    for (int c = 0; c < nc; ++c) d_[c] = r_[c] + beta * d_[c];
    op_.apply(d_, q_);
    double den = 0.0;
    for (int c = 0; c < nc; ++c) den += (stick * q_[c] * d_[c]).sum();
    if (!(den > 0.0)) break;
    const double alpha = rr / den;
    for (int c = 0; c < nc; ++c) psi_[c] += alpha * d_[c], u_[c] += alpha * q_[c];
  }
  if (!(res.residual <= tol_)) {
    std::ostringstream msg;
    msg << "stiffness solve did not converge: residual " << res.residual << " after "
        << res.iterations << " iterations";
    throw SolverError(msg.str());
  }
  res.kx = psi_[0].sum() * op_.grid().cell_area();
  last_stick_ = stick;
  last_kx_ = res.kx;
  return res;
}

}  // namespace fretbem
