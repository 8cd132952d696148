#include "workspace.hpp"

#include <sstream>

#include "fretbem/core/errors.hpp"

namespace fretbem::tangential_detail {

Workspace::Workspace(TangentialOperator& op_, const TangentialIncrement& inc_,
                     TangentialOptions opt_, BoundCache& cache)
    : op(op_),
      inc(inc_),
      opt(opt_),
      conv0(op_.half_space().convolutions()),
      sets(cache.update(op_, *inc_.bound), op_.half_space().communicator()) {
  scale = cache.scale();
  gsum = cache.gsum();
  const double fmax = gsum * op.grid().cell_area();
  if (past_full_sliding(inc, fmax, opt.tolerance)) {
    std::ostringstream msg;
    msg << "tangential force " << inc.target.norm() << " N is not below the full-sliding force "
        << "mu F_z = " << fmax << " N: force control cannot go past full sliding";
    throw SolverError(msg.str());
  }
  slip.val.resize(op.components());
  slip.back_val.resize(op.components());
}

// A guess that already meets the solver's own stopping rule is the answer: the starts it would
// be compared against (one or two products under force control) are then not built. On a
// steady cycle the predictor's guess is of this kind at every step (3 products per step
// otherwise, 1 with this).
void Workspace::start(VecField& tau, VecField& u) {
  VecField tg, ug;
  const bool guess = inc.guess && feasible_guess(tg, ug);
  double stick_slip2 = 0.0;
  const double res = guess ? residual(tg, ug, stick_slip2) : 0.0;
  if (guess && res <= opt.tolerance) {
    tau = std::move(tg), u = std::move(ug), exact = true;
    start_residual = {res, stick_slip2};
    return;
  }
  if (guess && inc.guess_continues) {
    tau = std::move(tg), u = std::move(ug), exact = true;
    return;
  }
  // The warm start is made feasible only when no guess replaced it (a pass of the grid).
  const bool moved = project_all(*inc.bound, tau, comm());
  if (moved || u.size() != tau.size()) op.apply(tau, u), exact = true;
  if (inc.control == TangentialControl::force) start_force(tau, u);
  if (guess && energy(tg, ug) < energy(tau, u))
    tau = std::move(tg), u = std::move(ug), exact = true;
}

double Workspace::energy(const VecField& t, const VecField& w) const {
  double e = 0.0;
  for (std::size_t c = 0; c < t.size(); ++c) {
    const Field dt = t[c] - (*inc.tau0)[c];
    e += 0.5 * (dt * (w[c] - (*inc.u0)[c])).sum();
    // Under force control sum dtau is fixed, so the shift term is the same for every start.
    if (inc.control == TangentialControl::displacement) e -= inc.target(c) * dt.sum();
  }
  return comm().sum(e);
}

// The predictor made feasible (inside the discs; under force control shifted to the target
// force as start_force does) and imaged by one product; false when no shift reaches the target
// force. A predictor close to the solution (the same step of the previous cycle of a periodic
// history) then leaves the solver little or nothing to do.
bool Workspace::feasible_guess(VecField& tg, VecField& ug) {
  const Field& g = *inc.bound;
  tg = *inc.guess;
  if (tg.size() != inc.tau0->size()) return false;
  project_all(g, tg, comm());
  if (inc.control == TangentialControl::force) {
    const double tol = 1e-15 * gsum;
    const Eigen::VectorXd want = inc.target / op.grid().cell_area();
    sets.classify(g, tg);
    if (shift_to_force(Movable::stick, want, tg).mismatch > tol &&
        shift_to_force(Movable::all, want, tg).mismatch > tol)
      return false;
  }
  op.apply(tg, ug);
  return true;
}

double Workspace::residual(const VecField& tau, const VecField& u, double& stick_slip2) {
  return tangential_detail::residual(sets, inc, tau, u, scale, op.grid(), result.shift,
                                     stick_slip2);
}

// Force control: of the two feasible starts of the right force — shifting the stick nodes
// only (continued loading) or every contact node (a reversal, where the whole contact sticks
// again first) — take the one of lower QP energy 1/2 (tau - tau0) . (u - u0).
void Workspace::start_force(VecField& tau, VecField& u) {
  const Field& g = *inc.bound;
  const double area = op.grid().cell_area(), tol = 1e-15 * gsum;
  const Eigen::VectorXd want = inc.target / area;
  if ((total_force(tau, op.grid(), comm()) / area - want).norm() <= tol) return;
  VecField ta = tau, ua, tb = tau, ub;
  sets.classify(g, tau);
  const bool a_ok = shift_to_force(Movable::stick, want, ta).mismatch <= tol;
  shift_to_force(Movable::all, want, tb);
  op.apply(tb, ub);
  if (a_ok) {
    op.apply(ta, ua);
    if (energy(ta, ua) < energy(tb, ub)) {
      tau = std::move(ta), u = std::move(ua), exact = true;
      return;
    }
  }
  tau = std::move(tb), u = std::move(ub), exact = true;
}

TangentialResult Workspace::finish(const VecField& tau, const std::string& algorithm) {
  result.convolutions = int(op.half_space().convolutions() - conv0);
  result.force = total_force(tau, op.grid(), comm());
  if (!result.converged) {
    std::ostringstream msg;
    msg << algorithm << " tangential solver did not converge: residual " << result.residual
        << " > tolerance " << opt.tolerance << " after " << result.iterations << " iterations";
    throw SolverError(msg.str());
  }
  return result;
}

}  // namespace fretbem::tangential_detail
