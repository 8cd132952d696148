// The ODE wear integrator: dW/dN = w(z0 - W) by ARKODE from snapshot to snapshot, with the
// cost guard's stretches of cycles, the rows' accepted flags, snapshots and checkpoints.
#include <arkode/arkode_arkstep.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

#include "arkode_stepper.hpp"
#include "fretbem/core/errors.hpp"
#include "fretbem/wear/cost_estimate.hpp"
#include "ode_data.hpp"
#include "wear_rows.hpp"

namespace fretbem::wear_detail {
namespace {

// Logs the rows of one integrator step (evaluations from rep.history[first] on) with their
// accepted flag: an evaluation is accepted when it ran on the state before or after the step
// (W and N equal) and that state has no accepted row yet, so N increases over accepted rows.
// `last` (N, fingerprint) is the state with the latest accepted row; `final_state`: the state
// after the step is the final one, whose accepted row is the final observation instead.
void flush_step(WearReport& rep, std::size_t first, Observer& log, double t0, std::uint64_t h0,
                double t1, std::uint64_t h1, bool final_state,
                std::pair<double, std::uint64_t>& last) {
  for (std::size_t k = first; k < rep.history.size(); ++k) {
    WearCycle& c = rep.history[k];
    const std::pair<double, std::uint64_t> key{c.N, c.worn_hash};
    const bool before = key == std::pair{t0, h0}, after = key == std::pair{t1, h1};
    c.accepted = (before || (after && !final_state)) && key != last;
    if (c.accepted) last = key;
    log.cycle(c);
  }
}

// N += L - 1 + share cycles one by one from (t, W): the steady cycle of W, then the physical
// history (tractions carried, each cycle's wear applied before the next); the last cycle's
// wear is applied times share (0, 1], an Euler step of less than the cycle arithmetic's one
// cycle, so that a stretch that started between whole cycles ends on a snapshot. Every row
// is a point of the solution (accepted).
double cycle_stretch(WearCycles& cyc, WearReport& rep, Observer& log, double t, Field& W, long L,
                     double share, std::pair<double, std::uint64_t>& last,
                     const Communicator& comm) {
  for (long k = 0; k < L; ++k) {
    WearCycle c = k == 0 ? cyc.steady(t, W) : cyc.continued(t);
    c.worn_hash = fingerprint(W, comm);
    // The state the stretch starts from may have its accepted row already (the integrator
    // step's last evaluation).
    const std::pair<double, std::uint64_t> key{t, c.worn_hash};
    c.accepted = key != last;
    last = key;
    const bool final = k + 1 == L;
    W += final ? share * c.rate : c.rate;
    t += final ? share : 1.0;
    if (!final) cyc.apply(c.rate);
    keep(rep, std::move(c), log);
  }
  ++rep.stretches;
  rep.stretch_cycles += double(L - 1) + share;
  return t;
}

/// Where an integrator step started: its time, simulated cycles, state and first row.
struct StepStart {
  double t = 0.0, simulated = 0.0;
  std::uint64_t worn_hash = 0;
  std::size_t first_row = 0;
};

/// One ODE wear run: the ARKODE stepper, its user data and where the run stands.
class OdeRun {
 public:
  OdeRun(Model& model, WearCycles& cyc, Observer& log, WearIntegrator kind,
         const WearCheckpoint* resume);
  WearReport run(long max_steps);

 private:
  Eigen::Map<Field> worn() { return slab(d_, y_); }
  std::uint64_t worn_fingerprint() {
    return fingerprint(worn(), model_.half_space->communicator());
  }
  void resume_from(const WearCheckpoint& at);
  void first_cycle();
  bool choose_implicit(WearIntegrator kind) const;
  bool advance(std::size_t i, long max_steps);
  StepStart evolve_step(std::size_t i);
  void guard_cost(const StepStart& s, std::size_t i);
  void stretch_to(std::size_t i);
  double restart(std::size_t i, double h_next);
  void write_checkpoint(std::size_t i, bool snap, double h_next, long steps, long fails);
  WearReport finish();

  Model& model_;
  WearCycles& cyc_;
  Observer& log_;
  const WearCheckpoint* resume_;
  const double N_end_;
  const std::vector<double> snaps_;
  WearReport rep_;
  SunContext sun_;
  OdeData d_;
  GridVector y_owner_;
  N_Vector y_;
  double t_ = 0.0, cap_ = INFINITY;
  std::size_t first_snap_ = 1;
  long steps0_ = 0, rejected0_ = 0;
  // The state whose accepted row is out.
  std::pair<double, std::uint64_t> last_;
  bool implicit_ = false;
  ArkodeStepper it_;
  long taken_ = 0;
  double stretch_ = kMinStretch;
  bool stretched_ = false;     // the previous wear step was a stretch of cycles
  double stretch_left_ = 0.0;  // cycles of the current stretch still to simulate
  double step_cost_ = 0.0;     // simulated cycles of the last integrator step weighed
  bool unpaid_ = false;        // that step was not kStepWorth times cheaper than its cycles
  double h_next_ = 0.0;        // the integrator's next step
};

OdeRun::OdeRun(Model& model, WearCycles& cyc, Observer& log, WearIntegrator kind,
               const WearCheckpoint* resume)
    : model_(model),
      cyc_(cyc),
      log_(log),
      resume_(resume),
      N_end_(model.scenario.wear.cycles),
      snaps_(snapshot_cycles(N_end_)),
      d_{model, cyc, rep_},
      y_owner_(new_grid_vector(*model.half_space, sun_.ctx)),
      y_(y_owner_.get()) {
  N_VConst(0.0, y_);
  if (resume)
    resume_from(*resume);
  else
    first_cycle();
  d_.atol = resume && resume->atol > 0.0 ? resume->atol : absolute_tolerance(model_, cyc_);
  // The state a checkpoint holds has its accepted row already when a step's last evaluation
  // ran on it (the checkpoint says so); otherwise its row is the first evaluation of the next
  // step, and a resumed run starts with none (a resume row written with accepted = 0 would
  // hide an accepted state).
  const bool has_row = !resume || resume->state_has_row;
  last_ = has_row ? std::pair{t_, worn_fingerprint()} : std::pair{-1.0, std::uint64_t(0)};
  implicit_ = choose_implicit(kind);
  rep_.implicit = implicit_;
  if (!resume) {
    const SimulatedCycles e = expected_simulated_cycles(model_.scenario, implicit_, cap_,
                                                        cyc_.simulated(), rep_.history.front());
    log_.expect(e.low, e.high);
  }
  if (implicit_) {
    d_.pre = std::make_unique<WearPreconditioner>(*model_.half_space,
                                                  model_.path.steps.front().normal.force_control);
  }
  it_.implicit = implicit_;
  create(it_, y_, sun_.ctx, d_, std::min(cap_, N_end_));
  // A resumed run restarts a fresh integrator at (N, W) with the step it was about to try.
  // The explicit integrator restarts so after every step anyway (restart): resuming repeats
  // the uninterrupted run. The implicit one loses its step-size and Newton history: close to,
  // not bit-identical with, the uninterrupted run (docs/wear.md).
  if (resume) check(it_.reset(t_, y_, std::min(resume->h_next, N_end_ - t_)), "restart");
}

void OdeRun::resume_from(const WearCheckpoint& at) {
  worn() = at.worn;
  t_ = at.N, cap_ = at.h_max;
  first_snap_ = std::size_t(at.next_snapshot);
  steps0_ = at.steps, rejected0_ = at.rejected;
  cyc_.resume(at.counters, at.warm);
  if (at.stretch > 0.0) stretch_ = at.stretch, stretched_ = at.stretched;
  stretch_left_ = at.stretch_left, step_cost_ = at.step_cost, unpaid_ = at.step_unpaid;
  h_next_ = at.h_next;
}

// A first steady cycle on the unworn surface: the N = 0 row, snapshot and stability cap.
void OdeRun::first_cycle() {
  cyc_.start();
  const Field unworn = model_.half_space->local_zeros();
  WearCycle c0 = cyc_.steady(0.0, unworn);
  c0.accepted = true;
  c0.worn_hash = worn_fingerprint();
  log_.snapshot(0.0, unworn, cyc_.pressure(), true);
  cap_ = explicit_step_cap(model_, c0.max_slip);
  require_ode_cap(model_.scenario.wear, cap_);
  keep(rep_, std::move(c0), log_);
  if (const std::string w = explicit_cap_warning(model_.scenario.wear, cap_); !w.empty())
    log_.warn(w);
}

// The cap of the unworn surface decides arkode's method; a resumed run keeps that choice.
bool OdeRun::choose_implicit(WearIntegrator kind) const {
  if (resume_)
    return kind != WearIntegrator::erk && (kind == WearIntegrator::dirk || resume_->implicit);
  return runs_implicit(kind, N_end_, cap_, cyc_.simulated());
}

WearReport OdeRun::run(long max_steps) {
  for (std::size_t i = first_snap_; i < snaps_.size() && !rep_.stopped; ++i) {
    check(it_.stop(snaps_[i]), "stop time");
    while (t_ < snaps_[i])
      if (!advance(i, max_steps)) break;
  }
  return finish();
}

// One wear step towards snapshot i: an integrator step, then cycles one by one where it was
// not profitable; or, while a stretch runs on past a snapshot, its cycles to the next one.
// False when the run is at its end or stopped.
bool OdeRun::advance(std::size_t i, long max_steps) {
  // After a step that did not pay, a step that could cover no more than kStepWorth times its
  // cost before the snapshot (where the integrator stops) cannot pay either: the cycles up to
  // the snapshot one by one instead.
  if (unpaid_ && stretch_left_ <= 0.0 && snaps_[i] - t_ < kStepWorth * step_cost_) {
    stretch_left_ = std::ceil(snaps_[i] - t_);
    stretched_ = true;
  }
  if (stretch_left_ <= 0.0) {
    const StepStart s = evolve_step(i);
    const bool final_state = t_ >= N_end_;
    flush_step(rep_, s.first_row, log_, s.t, s.worn_hash, t_, worn_fingerprint(), final_state,
               last_);
    if (final_state) return false;
    // The explicit step obeys the new cap from its first attempt on.
    h_next_ = implicit_ ? it_.next_step() : std::min(it_.next_step(), cap_);
    guard_cost(s, i);
  }
  if (stretch_left_ > 0.0) stretch_to(i);
  if (t_ >= N_end_) return false;
  const bool snap = t_ >= snaps_[i];
  if (snap) log_.snapshot(t_, worn(), cyc_.pressure_on(worn()), false);
  long steps = 0, fails = 0;  // counted before a restart
  it_.stats(steps, fails);
  h_next_ = restart(i, h_next_);
  write_checkpoint(i, snap, h_next_, steps, fails);
  if ((max_steps >= 0 && ++taken_ >= max_steps) || log_.stop_requested()) {
    rep_.stopped = true;
    return false;
  }
  return true;
}

StepStart OdeRun::evolve_step(std::size_t i) {
  d_.step_max_slip = 0.0;
  const StepStart s{t_, cyc_.simulated(), worn_fingerprint(), rep_.history.size()};
  const int flag = it_.evolve(snaps_[i], y_, &t_);
  if (d_.error) std::rethrow_exception(d_.error);
  check(flag, "step", t_);
  if (!implicit_) {
    cap_ = explicit_step_cap(model_, d_.step_max_slip);
    check(it_.max_step(cap_), "max step");
  }
  return s;
}

// Cost guard (wear_rows.hpp): after an integrator step that was not cheaper than its cycles,
// a stretch of cycles, doubled when the wear step before was a stretch too. A step that ended
// on snapshot i was cut short by the stop time and says nothing of a longer one: no stretch
// (advance simulates the next interval cycle by cycle when it is too short to pay for it).
void OdeRun::guard_cost(const StepStart& s, std::size_t i) {
  const double cost = cyc_.simulated() - s.simulated;
  step_cost_ = cost;
  unpaid_ = kStepWorth * cost > t_ - s.t;
  const bool cut = t_ >= snaps_[i] - 1e-9 * std::max(1.0, snaps_[i]);
  if (!unpaid_ || cut) {
    stretched_ = false;
    return;
  }
  // At least the failed step's cost: every step but the last costs at most the cycles the
  // stretch after it simulates.
  stretch_ = std::max(stretched_ ? 2.0 * stretch_ : kMinStretch, cost);
  stretch_left_ = std::floor(stretch_);
  stretched_ = true;
}

// The current stretch's cycles up to snapshot i. A stretch that reaches the snapshot ends
// there (its last cycle shortened when it started between whole cycles) and runs on in the
// next interval: a snapshot is an observation, and an integrator step cut short by it cannot
// be cheaper than its cycles. For the same reason a stretch that would end short of the
// snapshot by less than kStepWorth times the failed step's cost runs on to it (the integrator
// stops there, so its step could cover no more than that rest). Each piece starts from the
// steady cycle of W, as the resumed run does from a checkpoint at the snapshot.
void OdeRun::stretch_to(std::size_t i) {
  // t may sit a rounding error below a whole number.
  const double eps = 1e-9 * std::max(1.0, snaps_[i]);
  const double to_snap = snaps_[i] - t_;
  if (to_snap <= eps) return;  // the integrator step ended on the snapshot
  // Also a stretch ending less than a cycle before the snapshot: a step over the rest costs
  // at least one evaluation, more than the cycle does.
  const double rest = to_snap - stretch_left_;
  const bool reaches = rest < std::max(1.0, kStepWorth * step_cost_) + eps;
  const long L = reaches ? long(std::ceil(to_snap - eps)) : long(stretch_left_);
  const double share = reaches ? to_snap - double(L - 1) : 1.0;
  Field W = worn();
  t_ = cycle_stretch(cyc_, rep_, log_, t_, W, L, std::clamp(share, 0.0, 1.0), last_,
                     model_.half_space->communicator());
  worn() = W;
  if (reaches) t_ = snaps_[i];
  stretch_left_ = reaches ? std::max(0.0, stretch_left_ - to_snap) : 0.0;
  if (stretch_left_ < 1.0) stretch_left_ = 0.0;  // whole cycles only
}

// SUNDIALS 6.4 ERKStep treats a table with c_s = 1 as first-same-as-last and reuses the last
// stage's f(t + h, y + h k1) as the next step's f(t_{n+1}, y_{n+1}): for Heun–Euler
// (b = (1/2, 1/2) != a_2 = (1, 0)) one evaluation per step instead of two, and not the method
// (y' = y, h = 0.1, 10 steps: 2.70838 instead of Heun's 2.71408; measured with the installed
// 6.4.1). A restart at the accepted (t, y) makes ARKODE evaluate f there — the correct first
// stage and the accepted row of the step — and is exactly what a resumed run does, so
// resuming is the uninterrupted run. After a stretch of cycles both integrators restart at its
// end, with a step long enough to pay for the failed step's cost, in whole cycles (a shorter
// one cannot be cheaper than its cycles; the explicit one within its cap). Returns the step to
// attempt next.
double OdeRun::restart(std::size_t i, double h_next) {
  if (implicit_ && !stretched_) return h_next;
  if (stretched_ && stretch_left_ <= 0.0) {
    h_next = std::max(h_next, std::ceil(kStepWorth * step_cost_));
    if (!implicit_) h_next = std::min(h_next, cap_);
  }
  h_next = std::min(h_next, N_end_ - t_);
  check(it_.reset(t_, y_, h_next), "restart");
  check(it_.stop(snaps_[i]), "stop time");
  return h_next;
}

void OdeRun::write_checkpoint(std::size_t i, bool snap, double h_next, long steps, long fails) {
  WearCheckpoint at;
  at.N = t_;
  at.worn = worn();
  at.h_next = h_next;
  at.h_max = cap_;
  at.counters = cyc_.counters();
  at.steps = steps0_ + steps, at.rejected = rejected0_ + fails;
  at.next_snapshot = long(snap ? i + 1 : i);
  at.implicit = implicit_;
  at.warm = cyc_.warm_start();
  at.state_has_row = last_ == std::pair{t_, worn_fingerprint()};
  at.stretch = stretch_, at.stretched = stretched_, at.stretch_left = stretch_left_;
  at.step_cost = step_cost_, at.step_unpaid = unpaid_;
  at.atol = d_.atol;
  log_.step_done(at);
}

WearReport OdeRun::finish() {
  it_.stats(rep_.steps, rep_.rejected);
  if (implicit_) {
    ARKStepGetNumNonlinSolvIters(it_.mem, &rep_.newton_iterations);
    ARKStepGetNumNonlinSolvConvFails(it_.mem, &rep_.newton_failures);
    ARKStepGetNumLinIters(it_.mem, &rep_.krylov_iterations);
    rep_.inner_iterations = d_.pre->iterations();
  }
  rep_.steps += steps0_, rep_.rejected += rejected0_;
  rep_.worn = worn();
  rep_.N = t_;
  if (!rep_.stopped) {
    // The final surface: one more steady cycle to observe it (its wear is not applied).
    WearCycle c = cyc_.steady(N_end_, rep_.worn);
    c.accepted = true;
    log_.snapshot(N_end_, rep_.worn, cyc_.pressure(), true);
    keep(rep_, std::move(c), log_);
    rep_.N = N_end_;
  }
  cyc_.wear_to(rep_.worn);
  rep_.simulated_cycles = cyc_.simulated();
  rep_.rhs_evaluations = cyc_.evaluations();
  return std::move(rep_);
}

}  // namespace

WearReport integrate_ode(Model& model, WearCycles& cyc, Observer& log, WearIntegrator kind,
                         const WearCheckpoint* resume, long max_steps) {
  return OdeRun(model, cyc, log, kind, resume).run(max_steps);
}

}  // namespace fretbem::wear_detail
