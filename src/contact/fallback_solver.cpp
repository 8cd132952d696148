// FallbackTangentialSolver: the chosen algorithm, then the other one, then sub-steps.
#include <Eigen/Dense>
#include <cmath>
#include <cstdio>

#include "fretbem/contact/tangential_solver.hpp"
#include "fretbem/core/errors.hpp"
#include "workspace.hpp"

namespace fretbem {

FallbackTangentialSolver::FallbackTangentialSolver(TangentialOperator& op, double tolerance,
                                                   std::unique_ptr<TangentialSolver> primary,
                                                   std::unique_ptr<TangentialSolver> secondary)
    : grid_(op.grid()),
      comm_(op.half_space().communicator()),
      tolerance_(tolerance),
      self_compliance_(op.self_compliance()),
      primary_(std::move(primary)),
      secondary_(std::move(secondary)) {}

bool FallbackTangentialSolver::try_solve(TangentialSolver& s, const TangentialIncrement& inc,
                                         VecField& tau, VecField& u, TangentialResult& r) {
  const VecField tau_in = tau, u_in = u;
  try {
    r = s.solve(inc, tau, u);
    return true;
  } catch (const SolverError&) {
    tau = tau_in, u = u_in;  // the next attempt starts from the same warm start
    return false;
  }
}

void FallbackTangentialSolver::announce(const std::string& what) {
  ++fallbacks_;
  if (announced_) return;
  announced_ = true;
  std::fprintf(stderr,
               "\nfretbem: note: a tangential increment did not converge with the chosen "
               "algorithm; solved by %s (said once per run)\n",
               what.c_str());
}

TangentialResult FallbackTangentialSolver::solve(const TangentialIncrement& inc, VecField& tau,
                                                 VecField& u) {
  const VecField tau_in = tau, u_in = u;
  try {
    return primary_->solve(inc, tau, u);
  } catch (const SolverError& first) {
    // Force control at or past full sliding is an impossible load, not a hard increment.
    if (tangential_detail::past_full_sliding(inc, grid_, 0.0, comm_)) throw;
    tau = tau_in, u = u_in;
    TangentialResult r;
    if (try_solve(*secondary_, inc, tau, u, r)) {
      announce("the other algorithm (solver.algorithm)");
      return r;
    }
    if (inc.control == TangentialControl::force) {
      tau = tau_in, u = u_in;
      if (force_by_shift(inc, tau, u, r)) {
        announce("displacement-controlled solves for the shift that carries the force");
        return r;
      }
    }
    for (int m = 2; m <= kMaxSubsteps; m *= 2) {
      tau = tau_in, u = u_in;
      if (substeps(m, inc, tau, u, r)) {
        announce(std::to_string(m) + " sub-steps");
        return r;
      }
    }
    throw;
  }
}

// Force control as displacement control: the total force F(dU) of the displacement-controlled
// increment is the gradient of a convex function of dU (the QP's dual), hence monotone, and
// displacement control converges where the force-constrained iteration can fail (measured:
// rough surface, Cerruti, 0.93 mu F_z, the force carried by 3 stick nodes). Broyden's method
// on F(dU) = target with backtracking on |F - target|, started from the compliance estimate
// of the contact (one node's compliance spread over sqrt(N) neighbours).
bool FallbackTangentialSolver::force_by_shift(const TangentialIncrement& inc, VecField& tau,
                                              VecField& u, TangentialResult& r) {
  const int nc = int(inc.target.size());
  const double fmax = tangential_detail::bound_force(*inc.bound, grid_, comm_);
  const double tol = tolerance_ * fmax;
  TangentialIncrement d = inc;
  d.control = TangentialControl::displacement;
  int iterations = 0, convolutions = 0;
  auto force_at = [&](const Eigen::VectorXd& dU, VecField& t, VecField& w, Eigen::VectorXd& F) {
    d.target = dU;
    TangentialResult rk;
    if (!try_solve(*primary_, d, t, w, rk) && !try_solve(*secondary_, d, t, w, rk)) return false;
    iterations += rk.iterations, convolutions += rk.convolutions;
    F = rk.force, r = rk;
    return true;
  };
  const double nodes = std::max(1.0, comm_.sum(double((*inc.bound > 0.0).count())));
  const double compliance = self_compliance_ * std::sqrt(nodes) / (nodes * grid_.cell_area());
  Eigen::MatrixXd B = Eigen::MatrixXd::Identity(nc, nc) / compliance;  // dF/dU estimate
  Eigen::VectorXd dU = Eigen::VectorXd::Zero(nc), F;
  if (!force_at(dU, tau, u, F)) return false;
  for (int it = 0; it < kShiftIterations; ++it) {
    const Eigen::VectorXd e = F - inc.target;
    if (e.norm() <= tol) {
      r.iterations = iterations, r.convolutions = convolutions, r.shift = dU;
      return true;
    }
    Eigen::VectorXd step = B.fullPivLu().solve(-e);
    VecField t = tau, w = u;
    Eigen::VectorXd Fn;
    double lambda = 1.0;
    for (;; lambda *= 0.5) {  // backtracking: the merit |F - target| must fall
      t = tau, w = u;
      if (!force_at(dU + lambda * step, t, w, Fn)) return false;
      if ((Fn - inc.target).norm() < e.norm() || lambda < 1e-6) break;
    }
    const Eigen::VectorXd s = lambda * step, y = Fn - F;
    if (s.squaredNorm() > 0.0) B += (y - B * s) * s.transpose() / s.squaredNorm();
    dU += s, F = Fn, tau = std::move(t), u = std::move(w);
  }
  return false;
}

// m equal sub-steps of the load, each solved by the chosen algorithm or else the other one.
bool FallbackTangentialSolver::substeps(int m, const TangentialIncrement& inc, VecField& tau,
                                        VecField& u, TangentialResult& r) {
  const Grid& grid = grid_;
  Eigen::VectorXd start = inc.target * 0.0;
  if (inc.control == TangentialControl::force) {
    VecField tau0 = *inc.tau0;
    tangential_detail::project_all(*inc.bound, tau0, comm_);
    start = tangential_detail::total_force(tau0, grid, comm_);
  }
  TangentialResult total;
  total.shift = Eigen::VectorXd::Zero(inc.target.size());
  VecField tau0 = *inc.tau0, u0 = *inc.u0;
  for (int k = 1; k <= m; ++k) {
    TangentialIncrement part = inc;
    part.tau0 = &tau0, part.u0 = &u0;
    part.target = inc.control == TangentialControl::force
                      ? Eigen::VectorXd(start + (inc.target - start) * (double(k) / m))
                      : Eigen::VectorXd(inc.target / m);
    TangentialResult rk;
    if (!try_solve(*primary_, part, tau, u, rk) && !try_solve(*secondary_, part, tau, u, rk))
      return false;
    total.iterations += rk.iterations, total.convolutions += rk.convolutions;
    total.shift += rk.shift;
    total.residual = rk.residual, total.force = rk.force, total.converged = true;
    tau0 = tau, u0 = u;
  }
  r = total;
  return true;
}

}  // namespace fretbem
