// FallbackTangentialSolver: the chosen algorithm, then the other one, then sub-steps.
#include <cstdio>

#include "fretbem/contact/tangential_solver.hpp"
#include "fretbem/core/errors.hpp"
#include "tangential_detail.hpp"

namespace fretbem {

FallbackTangentialSolver::FallbackTangentialSolver(const Grid& grid,
                                                   std::unique_ptr<TangentialSolver> primary,
                                                   std::unique_ptr<TangentialSolver> secondary)
    : grid_(grid), primary_(std::move(primary)), secondary_(std::move(secondary)) {}

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
    if (tangential_detail::past_full_sliding(inc, grid_, 0.0)) throw;
    tau = tau_in, u = u_in;
    TangentialResult r;
    if (try_solve(*secondary_, inc, tau, u, r)) {
      announce("the other algorithm (solver.algorithm)");
      return r;
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

// m equal sub-steps of the load, each solved by the chosen algorithm or else the other one.
bool FallbackTangentialSolver::substeps(int m, const TangentialIncrement& inc, VecField& tau,
                                        VecField& u, TangentialResult& r) {
  const Grid& grid = grid_;
  Eigen::VectorXd start = inc.target * 0.0;
  if (inc.control == TangentialControl::force) {
    VecField tau0 = *inc.tau0;
    tangential_detail::project_all(*inc.bound, tau0);
    start = tangential_detail::total_force(tau0, grid);
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
