#include "tangential_detail.hpp"

#include <cmath>
#include <sstream>

#include "fretbem/errors.hpp"

namespace fretbem::tangential_detail {

Field magnitude(const VecField& tau) {
  Field m = tau[0].square();
  for (std::size_t c = 1; c < tau.size(); ++c) m += tau[c].square();
  return m.sqrt();
}

Field free_mask(const Field& g, const Field& mag) {
  return ((g > 0.0) && (mag < g * (1.0 - kBoundEps))).cast<double>();
}

Eigen::VectorXd total_force(const VecField& tau, const Grid& grid) {
  Eigen::VectorXd F(tau.size());
  for (std::size_t c = 0; c < tau.size(); ++c) F(c) = tau[c].sum() * grid.cell_area();
  return F;
}

double bound_force(const Field& g, const Grid& grid) {
  return g.sum() * grid.cell_area();
}

Eigen::VectorXd shift_estimate(const TangentialIncrement& inc, const VecField& u,
                               const Field& free) {
  if (inc.control == TangentialControl::displacement) return inc.target;
  // Force control: the rigid shift is the common displacement increment of the stick nodes.
  const Field& w = free.sum() > 0 ? free : Field((*inc.bound > 0.0).cast<double>());
  const double n = std::max(1.0, w.sum());
  Eigen::VectorXd dU(u.size());
  for (std::size_t c = 0; c < u.size(); ++c) dU(c) = (w * (u[c] - (*inc.u0)[c])).sum() / n;
  return dU;
}

bool project_all(const Field& g, VecField& tau) {
  const Field mag = magnitude(tau);
  bool moved = false;
  for (Eigen::Index k = 0; k < g.size(); ++k) {
    if (mag(k) <= g(k)) continue;
    const double f = g(k) > 0.0 ? g(k) / mag(k) : 0.0;
    for (auto& t : tau) t(k) *= f;
    moved = true;
  }
  return moved;
}

double ScaleCache::get(TangentialOperator& op, const Field& g) {
  if (g_.size() == g.size() && (g_ == g).all()) return scale_;
  g_ = g;
  VecField load = op.zeros(), u;
  load[0] = g;
  op.apply(load, u);
  const Field contact = (g > 0.0).cast<double>();
  const double n = contact.sum();
  scale_ = n > 0 ? std::sqrt((contact * u[0].square()).sum() / n) : 1.0;
  if (!(scale_ > 0.0)) scale_ = 1.0;
  return scale_;
}

Workspace::Workspace(TangentialOperator& op_, const TangentialIncrement& inc_,
                     TangentialOptions opt_, ScaleCache& cache)
    : op(op_), inc(inc_), opt(opt_) {
  conv0 = op.half_space().convolutions();
  scale = cache.get(op, *inc.bound);
  if (inc.control == TangentialControl::force) {
    const double fmax = bound_force(*inc.bound, op.grid());
    if (!(inc.target.norm() < fmax)) {
      std::ostringstream msg;
      msg << "tangential force " << inc.target.norm() << " N is not below the full-sliding force "
          << "mu F_z = " << fmax << " N: force control cannot go past full sliding";
      throw SolverError(msg.str());
    }
  }
}

void Workspace::start(VecField& tau, VecField& u) {
  const bool moved = project_all(*inc.bound, tau);
  if (moved || u.size() != tau.size()) op.apply(tau, u);
  restore_force(tau, u);
}

void Workspace::restore_force(VecField& tau, VecField& u) {
  if (inc.control != TangentialControl::force) return;
  const Field& g = *inc.bound;
  const double area = op.grid().cell_area(), fmax = bound_force(g, op.grid());
  bool changed = false;
  for (int pass = 0; pass < 100; ++pass) {
    const Eigen::VectorXd err = inc.target - total_force(tau, op.grid());
    if (err.norm() <= 1e-15 * fmax) break;
    const Field free = free_mask(g, magnitude(tau));
    const double m = free.sum();
    if (m == 0.0) break;
    for (std::size_t c = 0; c < tau.size(); ++c) tau[c] += free * (err(c) / (m * area));
    project_all(g, tau);
    changed = true;
  }
  if (changed) op.apply(tau, u);
}

bool Workspace::project_and_reenter(const Field& free, VecField& tau, VecField& u) {
  const Field& g = *inc.bound;
  const int nc = op.components();
  const double omega = 1.0 / op.self_compliance();
  const Eigen::VectorXd dU = shift_estimate(inc, u, free);
  std::vector<std::int64_t> idx;
  std::vector<std::vector<double>> val(nc);
  bool set_changed = false;
  Eigen::VectorXd t(nc), y(nc);
  for (Eigen::Index k = 0; k < g.size(); ++k) {
    if (!(g(k) > 0.0)) continue;
    for (int c = 0; c < nc; ++c) t(c) = tau[c](k);
    if (free(k) > 0.0) {
      y = t;  // a stick node that left its disc is projected back onto it
    } else {
      // Slip node: Jacobi step along its slip; it stays on the bound if the slip points out.
      for (int c = 0; c < nc; ++c) y(c) = t(c) + omega * (dU(c) - (u[c](k) - (*inc.u0)[c](k)));
    }
    const double m = y.norm();
    if (m > g(k)) y *= g(k) / m;
    const bool now_free = y.norm() < g(k) * (1.0 - kBoundEps);
    set_changed |= now_free != (free(k) > 0.0);
    if ((y - t).norm() <= 1e-15 * g(k)) continue;
    idx.push_back(k);
    for (int c = 0; c < nc; ++c) val[c].push_back(y(c) - t(c)), tau[c](k) = y(c);
  }
  op.add_sparse(idx, val, tau, u);
  if (inc.control == TangentialControl::force) restore_force(tau, u);
  return set_changed;
}

TangentialResult Workspace::finish(const VecField& tau, const std::string& algorithm) {
  result.convolutions = int(op.half_space().convolutions() - conv0);
  result.force = total_force(tau, op.grid());
  if (!result.converged) {
    std::ostringstream msg;
    msg << algorithm << " tangential solver did not converge: residual " << result.residual
        << " > tolerance " << opt.tolerance << " after " << result.iterations << " iterations";
    throw SolverError(msg.str());
  }
  return result;
}

}  // namespace fretbem::tangential_detail
