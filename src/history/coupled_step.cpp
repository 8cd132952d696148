// Stepper::coupled_step: one load step with the normal-tangential coupling of dissimilar bodies
// (solver.coupling = coupled, Dundurs beta != 0). Tractions change the normal
// approach (Cerruti) and the pressure moves the surfaces tangentially (Boussinesq), so the
// normal and tangential problems of a step are solved alternately, each with the other's
// latest solution frozen (block Gauss-Seidel, as CONTACT's Panagiotopoulos process; Kalker,
// Three-dimensional elastic bodies in rolling contact, 1990, §5.2), until neither changes.
#include <cmath>
#include <limits>
#include <sstream>

#include "fretbem/history/stepper.hpp"

namespace fretbem {

namespace {

// |a - b| / |scale| in the L2 norm over the grid (0 when nothing changed, inf for a change
// against a zero scale).
double relative_change(const VecField& a, const VecField& b, const Field& scale) {
  double d2 = 0.0;
  for (std::size_t c = 0; c < a.size(); ++c) d2 += (a[c] - b[c]).square().sum();
  const double s2 = scale.square().sum();
  if (d2 == 0.0) return 0.0;
  return s2 > 0.0 ? std::sqrt(d2 / s2) : std::numeric_limits<double>::infinity();
}

// The bound an alternation ended on, g_prev = mu p_prev, carried to the new pressure p: mu
// kept wherever p_prev > 0, the law's bound of the step's start (g on entry) elsewhere. mu is
// what the law moved within the step (static/kinetic lowers it where a node slipped, evolving
// settles mu(X_1)); restarting it each alternation from the step's start re-solves the
// increment along a different path every time, and the inexact solves end a few solver
// tolerances apart however little p moved. A constant mu has nothing to carry (the law's mu p
// is the same bound without the rounding of p / p_prev).
void carry_bound(const Field& g_prev, const Field& p_prev, const Field& p, Field& g) {
  for (Eigen::Index k = 0; k < g.size(); ++k)
    if (p_prev(k) > 0.0) g(k) = g_prev(k) * (p(k) / p_prev(k));
}

// The tractions the last alternation left on their bound g_prev (within the solver tolerance
// eps), scaled onto the new bound g; true when one moved. The alternation's normal solve moves
// p, and so g = mu p, by a few 1e-3 to 1e-5 relative (case 45 of sweep seed 45); nodes whose g
// rose were left strictly inside their discs and the solver started them as stick nodes, so
// each re-solve found the slip zone again one node at a time (the stick set changed at every
// CG iteration: 36-49 iterations, 550-730 convolutions per re-solve at n = 32, as many as the
// first alternation's). A node on its bound stays on it: the last alternation's slip zone.
bool onto_new_bound(const Field& g_prev, const Field& g, double eps, VecField& tau) {
  bool moved = false;
  for (Eigen::Index k = 0; k < g.size(); ++k) {
    if (!(g_prev(k) > 0.0) || !(g(k) > 0.0)) continue;
    double t2 = 0.0;
    for (const Field& c : tau) t2 += c(k) * c(k);
    const double t = std::sqrt(t2);
    if (t < g_prev(k) * (1.0 - eps) || t == g(k)) continue;
    for (Field& c : tau) c(k) *= g(k) / t;
    moved = true;
  }
  return moved;
}

}  // namespace

// Alternation m: normal solve against the gap z - u_z(tau^{m-1}) (the approach the current
// tractions produce), bound mu p^m with mu as the last alternation left it (carry_bound);
// tangential increment from the step's start (tau0, u0) with the slip s = dU - (C tau - C tau0) -
// (w(p^m) - w(p0)), w the tangential displacement of the pressure, entered as a shifted u0 (the
// increment's QP is unchanged: the pressure's share is a known displacement field within it). Stops
// when the relative changes of p and tau from the previous alternation are both <=
// solver.coupling_tolerance; the state at the start of a step was converged, so an unchanged first
// alternation ends the step. So does one whose normal solve took no iteration: it left the pressure
// the last alternation's traction was solved against, so it solved that tangential problem again,
// and what tau still changes is the tangential solver's own tolerance (warm-started from its last
// solution it ends within tolerance elsewhere: two tractions 7.6e-6 apart in turn, residuals
// 7.4e-7 and 7.5e-7 at tolerance 1e-6, alternations 8-50 of a worn sphere's step at beta = 0.5).
// The step's start is the first iterate unless the load changed and
// the same step one repetition earlier ended closer (coupled_repeat.cpp). Where only the surface
// changed (a carried cycle's first step, after the cycle's wear) the last step's end is the
// answer within the tolerances: 1 alternation and 15 convolutions at sweep case 48/18.
bool Stepper::coupled_step(const LoadStep& ls, StepRecord& rec) {
  HalfSpace& hs = *model_.half_space;
  const SolverSpec& sv = model_.scenario.solver;
  TangentialIncrement probe;
  set_target(ls, probe);
  const bool same_normal = last_normal_ && *last_normal_ == ls.normal && !surface_changed_;
  const bool same_tangential =
      last_target_.size() == probe.target.size() &&
      (probe.control == TangentialControl::force ? last_target_ == probe.target
                                                 : probe.target.isZero(0.0));
  if (same_normal && same_tangential && !model_.friction->evolves()) return false;
  if (pressure_slip_.size() != 2) {
    pressure_slip_.assign(2, Field());
    hs.tangential_of_pressure(state_.pressure, pressure_slip_[0], pressure_slip_[1]);
  }
  const VecField tau0 = state_.traction, u0 = state_.displacement;
  const Field bound0 = bound_, pressure0 = state_.pressure;
  const bool repeated =
      !(last_normal_ && *last_normal_ == ls.normal && same_tangential) && start_from_repeat();
  VecField w(2), u0w(2);
  Field uz;
  TangentialResult r;
  int normal_iterations = 0, tangential_iterations = 0;
  // A law that settles its bound within the step (settle_bound) settles it in an alternation
  // only to a tenth of the last alternation's change, which the next one changes p by again
  // (the alternation contracts about tenfold): settled to solver.tolerance every time, the
  // flat punch of docs/performance.md, "Coupled", takes 489751 convolutions at step 4, 245233
  // so. Within ten tolerances the next alternation settles fully, and the step ends on one
  // that did.
  double floor = 0.0;
  const double tol = sv.coupling_tolerance;
  for (int it = 1;; ++it) {
    const Field p_prev = state_.pressure;
    const VecField tau_prev = state_.traction;
    const Field g_prev = bound_;
    hs.normal_of_traction(state_.traction[0], state_.traction[1], uz);
    solve_normal(ls, model_.surface - uz, rec);
    if (it > 1 && model_.friction->evolves()) carry_bound(g_prev, p_prev, state_.pressure, bound_);
    normal_iterations += rec.normal_iterations;
    if (it > 1 || repeated) onto_alternation_bound(it > 1 ? &g_prev : nullptr);
    hs.tangential_of_pressure(state_.pressure, w[0], w[1]);
    for (int c = 0; c < 2; ++c) u0w[c] = u0[c] - (w[c] - pressure_slip_[c]);
    bound_start_ = bound0, pressure_start_ = pressure0;  // settle_bound's start of the step
    r = coupled_tangential(ls, tau0, u0w, rec, floor);
    tangential_iterations += r.iterations;
    const double dp = relative_change({state_.pressure}, {p_prev}, state_.pressure);
    const double dt = relative_change(state_.traction, tau_prev, bound_);
    rec.coupling_iterations = it;
    rec.coupling_residual = std::max(dp, dt);
    if (rec.coupling_residual <= tol && floor <= tol) break;
    if (it > 1 && rec.normal_iterations == 0 && dp <= tol && floor <= tol) break;
    const bool settles = model_.friction->settles_within_step();
    floor = settles && rec.coupling_residual > 10 * tol ? 0.1 * rec.coupling_residual : 0.0;
    if (it >= sv.coupling_iterations) fail_coupling(rec, it, dp, dt, tau0, u0);
  }
  pressure_slip_ = w;
  remember_repeat();
  set_target(ls, probe);  // relative force targets follow the converged F_z
  last_target_ = probe.target;
  bound_start_ = bound0;
  pressure_start_ = pressure0;
  bound_moved_ = bound0.size() == bound_.size() && !(bound0 == bound_).all();
  rec.normal_iterations = normal_iterations;
  rec.tangential_iterations = tangential_iterations;
  rec.tangential_residual = r.residual;
  state_.shift += model_.tangential_operator->to_global(r.shift);
  accumulate_slip(u0w, &tau0, r.shift, rec);
  return true;
}

// The alternation's failure: where it stopped, by how much, and the state to reproduce it.
void Stepper::fail_coupling(StepRecord& rec, int alternations, double dp, double dt,
                            const VecField& tau0, const VecField& u0) {
  std::ostringstream msg;
  msg << "normal-tangential coupling did not converge (solver.coupling = coupled, beta = "
      << model_.scenario.material.dundurs_beta() << "): after " << alternations
      << " alternations the pressure still changed by " << dp << " and the traction by " << dt
      << " (relative) > " << model_.scenario.solver.coupling_tolerance
      << " (solver.coupling_tolerance)"
      << "; raise solver.coupling_iterations or the tolerance";
  FailedSolve f;
  f.solve = "coupling";
  f.surface = model_.surface, f.pressure_start = state_.pressure, f.bound = bound_;
  f.tau0 = tau0, f.u0 = u0;
  fail(rec, SolverError(msg.str()), std::move(f));
}

// The tractions the alternation starts its tangential solve from, put onto the bound its normal
// solve just set: those the last alternation left on `g_prev` (onto_new_bound), or, without one
// (the first alternation from the same step one repetition earlier, whose bound is not kept),
// those just inside the new bound (CyclePredictor::onto_moved_bound says why); their
// displacement C tau again when one moved.
void Stepper::onto_alternation_bound(const Field* g_prev) {
  const Communicator& comm = model_.half_space->communicator();
  if (!g_prev)
    CyclePredictor::onto_moved_bound(bound_, comm.max(bound_.maxCoeff()), state_.traction);
  else if (!comm.any(
               onto_new_bound(*g_prev, bound_, model_.scenario.solver.tolerance, state_.traction)))
    return;
  model_.tangential_operator->apply(state_.traction, state_.displacement);
}

// One tangential increment of an alternation, warm-started from the last one's traction; a
// failure names the step as tangential_step's do.
TangentialResult Stepper::coupled_tangential(const LoadStep& ls, const VecField& tau0,
                                             const VecField& u0, StepRecord& rec, double floor) {
  TangentialIncrement inc;
  inc.bound = &bound_;
  inc.tau0 = &tau0;
  inc.u0 = &u0;
  set_target(ls, inc);
  TangentialResult r = solve_increment(inc, tau0, u0, rec);
  const int iterations = r.iterations;
  r.iterations = iterations + settle_bound(inc, tau0, r, rec, floor);
  return r;
}

}  // namespace fretbem
