#include "tangential_detail.hpp"

#include <Eigen/Dense>
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
  if (inc.control == TangentialControl::force) start_force(tau, u);
}

// Force control: of the two feasible starts of the right force — shifting the stick nodes
// only (continued loading) or every contact node (a reversal, where the whole contact sticks
// again first) — take the one of lower QP energy 1/2 (tau - tau0) . (u - u0).
void Workspace::start_force(VecField& tau, VecField& u) {
  const Field& g = *inc.bound;
  const double area = op.grid().cell_area(), tol = 1e-15 * g.sum();
  const Eigen::VectorXd want = inc.target / area;
  if ((total_force(tau, op.grid()) / area - want).norm() <= tol) return;
  auto energy = [&](const VecField& t, const VecField& w) {
    double e = 0.0;
    for (std::size_t c = 0; c < t.size(); ++c)
      e += 0.5 * ((t[c] - (*inc.tau0)[c]) * (w[c] - (*inc.u0)[c])).sum();
    return e;
  };
  VecField ta = tau, ua, tb = tau, ub;
  const bool a_ok = shift_to_force(free_mask(g, magnitude(tau)), want, ta) <= tol;
  shift_to_force((g > 0.0).cast<double>(), want, tb);
  op.apply(tb, ub);
  if (a_ok) {
    op.apply(ta, ua);
    if (energy(ta, ua) < energy(tb, ub)) {
      tau = std::move(ta), u = std::move(ua);
      return;
    }
  }
  tau = std::move(tb), u = std::move(ub);
}

// Euclidean projection onto {|tau_i| <= g_i, sum tau h^2 = F} over a set of movable nodes:
// tau_i <- P_i(tau_i + lambda) with one shift lambda, found by safeguarded Newton on the
// monotone map lambda -> sum P_i(tau_i + lambda) (the gradient of a convex function; its
// Jacobian is the sum of the disc projections' Jacobians). Stick nodes move first: shifting
// slip nodes as well would turn them against their slip and, in 2-D, make the iteration cycle.
// Only when the stick nodes cannot carry the force (a reversal under force control) do all
// contact nodes move, which gives a feasible state of the right force.
void Workspace::restore_force(VecField& tau, VecField& u) {
  if (inc.control != TangentialControl::force) return;
  const Field& g = *inc.bound;
  const double area = op.grid().cell_area(), tol = 1e-15 * g.sum();
  const Eigen::VectorXd want = inc.target / area;
  if ((total_force(tau, op.grid()) / area - want).norm() <= tol) return;
  const Field stick = free_mask(g, magnitude(tau));
  const VecField before = tau;
  if (shift_to_force(stick, want, tau) > tol) {
    shift_to_force((g > 0.0).cast<double>(), want, tau);
    op.apply(tau, u);
    return;
  }
  if (!add_uniform_shift(stick, before, tau, u)) op.apply(tau, u);
}

// When the force correction moved every stick node by the same lambda (no node reached its
// bound) and the components are decoupled (analogy), u changes by lambda C 1_S: C 1_S is kept
// while the stick set S stays the same, so the correction costs no convolution.
bool Workspace::add_uniform_shift(const Field& stick, const VecField& before, const VecField& tau,
                                  VecField& u) {
  if (op.half_space().coupling() != Coupling::analogy) return false;
  const double n = stick.sum(), tol = 1e-13 * inc.bound->maxCoeff();
  if (!(n > 0.0)) return false;
  std::vector<double> lambda(tau.size());
  for (std::size_t c = 0; c < tau.size(); ++c) {
    const Field diff = tau[c] - before[c];
    lambda[c] = (stick * diff).sum() / n;
    if ((diff - lambda[c] * stick).abs().maxCoeff() > tol) return false;
  }
  if (stick_mask.size() != stick.size() || !(stick_mask == stick).all()) {
    VecField load = op.zeros(), w;
    load[0] = stick;
    op.apply(load, w);
    stick_mask = stick, stick_image = w[0];
  }
  for (std::size_t c = 0; c < tau.size(); ++c) u[c] += lambda[c] * stick_image;
  return true;
}

double Workspace::shift_to_force(const Field& movable, const Eigen::VectorXd& want,
                                 VecField& tau) const {
  const Field& g = *inc.bound;
  const int nc = int(tau.size());
  const VecField base = tau;
  auto apply = [&](const Eigen::VectorXd& l, Eigen::VectorXd& sum, Eigen::MatrixXd* J) {
    sum.setZero(nc);
    if (J) J->setZero(nc, nc);
    Eigen::VectorXd y(nc);
    for (Eigen::Index k = 0; k < g.size(); ++k) {
      for (int c = 0; c < nc; ++c) y(c) = base[c](k);
      if (movable(k) > 0.0) {
        y += l;
        const double m = y.norm();
        if (m <= g(k)) {
          if (J) *J += Eigen::MatrixXd::Identity(nc, nc);
        } else {
          if (J)
            *J += (g(k) / m) * (Eigen::MatrixXd::Identity(nc, nc) - y * y.transpose() / (m * m));
          y *= g(k) / m;
        }
        for (int c = 0; c < nc; ++c) tau[c](k) = y(c);
      }
      sum += y;
    }
  };
  Eigen::VectorXd lambda = Eigen::VectorXd::Zero(nc), sum(nc);
  Eigen::MatrixXd J(nc, nc);
  apply(lambda, sum, &J);
  double err = (sum - want).norm();
  for (int it = 0; it < 200 && err > 1e-15 * g.sum(); ++it) {
    // Newton step (regularised where the map is flat), halved until the mismatch shrinks.
    J += (1e-12 * J.trace() + 1e-300) * Eigen::MatrixXd::Identity(nc, nc);
    Eigen::VectorXd step = J.ldlt().solve(want - sum), trial(nc);
    int half = 0;
    for (; half < 60; ++half, step *= 0.5) {
      apply(lambda + step, trial, nullptr);
      if ((trial - want).norm() < err) break;
    }
    if (half == 60) break;  // no shift of these nodes reduces the mismatch
    lambda += step;
    apply(lambda, sum, &J);
    err = (sum - want).norm();
  }
  apply(lambda, sum, nullptr);
  return err;
}

bool Workspace::project_and_reenter(const Field& free, VecField& tau, VecField& u) {
  const Field& g = *inc.bound;
  const int nc = op.components();
  std::vector<std::int64_t> idx;
  std::vector<std::vector<double>> val(nc);
  // Stick nodes that the CG step carried out of their disc go back onto it.
  const Field mag = magnitude(tau);
  bool set_changed = false;
  for (Eigen::Index k = 0; k < g.size(); ++k) {
    if (!(free(k) > 0.0) || mag(k) <= g(k)) continue;
    idx.push_back(k);
    for (int c = 0; c < nc; ++c) {
      const double t = tau[c](k), y = t * g(k) / mag(k);
      val[c].push_back(y - t), tau[c](k) = y;
    }
    set_changed = true;
  }
  op.add_sparse(idx, val, tau, u);
  set_changed |= slip_node_step(free, tau, u);
  if (inc.control == TangentialControl::force) restore_force(tau, u);
  return set_changed;
}

// Slip nodes move along d = P(tau + omega s) - tau, omega = 1 / C_ii (a local Newton step: it
// turns a node towards its slip and lets a node slipping backwards re-enter its disc), with an
// exact line search on the QP: every point of the segment is feasible and the objective
// decreases, which a plain simultaneous Jacobi step on this dense operator would not ensure.
bool Workspace::slip_node_step(const Field& free, VecField& tau, VecField& u) {
  const Field& g = *inc.bound;
  const int nc = op.components();
  const double omega = 1.0 / op.self_compliance();
  const Eigen::VectorXd dU = shift_estimate(inc, u, free);
  std::vector<std::int64_t> idx;
  std::vector<std::vector<double>> val(nc);
  VecField d = op.zeros();
  double sd = 0.0;
  Eigen::VectorXd t(nc), y(nc), s(nc);
  for (Eigen::Index k = 0; k < g.size(); ++k) {
    if (!(g(k) > 0.0) || free(k) > 0.0) continue;
    for (int c = 0; c < nc; ++c) {
      t(c) = tau[c](k);
      s(c) = dU(c) - (u[c](k) - (*inc.u0)[c](k));
    }
    y = t + omega * s;
    const double over = std::max(0.0, y.norm() - g(k));
    if (over > 0.0) y *= g(k) / y.norm();
    // Moves at round-off level (projecting back onto the circle a node that slips outward)
    // are no moves: counting them would make every iteration a dense update.
    const double dd = (y - t).squaredNorm();
    if (!(dd > 1e-28 * g(k) * g(k))) continue;
    idx.push_back(k);
    for (int c = 0; c < nc; ++c) val[c].push_back(y(c) - t(c)), d[c](k) = y(c) - t(c);
    // s . d without cancellation: with y - t = omega s and t on the circle |t| = g,
    // s . d = (|d|^2 + (|y| - g) |d|^2 / (2 g)) / omega >= 0. The plain dot product loses the
    // O(angle^2) decrease of a small rotation in round-off and stalls near 1e-9 rad.
    sd += dd * (1.0 + over / (2.0 * g(k))) / omega;
  }
  if (idx.empty() || !(sd > 0.0)) return false;
  VecField w = op.zeros();
  op.add_sparse(idx, val, d, w);
  double dw = 0.0;
  for (int c = 0; c < nc; ++c) dw += (d[c] * w[c]).sum();
  const double theta = dw > 0.0 ? std::min(1.0, sd / dw) : 1.0;
  bool released = false;
  for (int c = 0; c < nc; ++c) tau[c] += theta * d[c], u[c] += theta * w[c];
  for (const auto k : idx) {
    double m2 = 0.0;
    for (int c = 0; c < nc; ++c) m2 += tau[c](k) * tau[c](k);
    const double m = std::sqrt(m2);
    // A damped turn (theta < 1) cuts the chord inside the disc; a node whose full step stayed
    // on the bound is put back on it, so turning does not release it. The O(theta |d|^2)
    // radial change is left out of u until the next exact product (see `dirty`).
    bool full_on_bound = true;
    double f2 = 0.0;
    for (int c = 0; c < nc; ++c) {
      const double t0 = tau[c](k) - theta * d[c](k), f = t0 + d[c](k);
      f2 += f * f;
    }
    full_on_bound = std::sqrt(f2) >= g(k) * (1.0 - kBoundEps);
    if (full_on_bound && m > 0.0 && m < g(k)) {
      for (int c = 0; c < nc; ++c) tau[c](k) *= g(k) / m;
      dirty = true;
    } else {
      released |= m < g(k) * (1.0 - kBoundEps);
    }
  }
  return released;
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
