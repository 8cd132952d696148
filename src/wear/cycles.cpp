// WearCycles: simulated cycles of the scenario's load path on a frozen surface (see
// wear_integrator.hpp for why the surface changes only between cycles).
#include <cmath>

#include "fretbem/contact/monotone_shortcut.hpp"
#include "fretbem/core/errors.hpp"
#include "fretbem/core/format.hpp"
#include "fretbem/history/cycle_summary.hpp"
#include "fretbem/history/slab_state.hpp"
#include "fretbem/wear/integrator.hpp"

namespace fretbem {

namespace {

// The steps after st[0] that a simulation needs: steps inside a monotone segment at constant
// normal load are dropped, since there the incremental solution does not depend on the step
// size and each node slips one way (Ciavarella–Jäger), so sum |s| over the segment is exact in
// one step (docs/architecture.md: one big increment on a monotone segment). A sine period
// keeps its turning points and end.
std::vector<LoadStep> merged(const std::vector<LoadStep>& st) {
  LoadPath p{st};
  std::vector<LoadStep> out;
  std::size_t kept = 0;
  for (std::size_t k = 1; k < st.size(); ++k)
    if (k + 1 == st.size() || st[k].turning || !p.monotone(kept, k + 1)) {
      out.push_back(st[k]);
      kept = k;
    }
  return out;
}

// One period of a periodic path, closed (its last step repeats its first step's loads), times
// as phases in [0, 1]. Sine: the path's first period (the path repeats it). Table: the whole
// table is the period; when its last row does not repeat its first row's loads, a closing step
// back to them ends the period. Turning points are those of the periodic path (the period's
// end is one when the motion reverses into the next period).
std::vector<LoadStep> one_period(const Scenario& sc, const LoadPath& path) {
  const auto& all = path.steps;
  const bool table = sc.load.path == PathType::table;
  // Step 0 is the normal loading at zero tangential load; a table whose first row has a
  // tangential load starts its period at step 1 (same time).
  const std::size_t p0 = table && all.size() > 1 && all[1].time == all[0].time ? 1 : 0;
  std::vector<LoadStep> st{all[p0]};
  for (std::size_t k = p0 + 1; k < all.size(); ++k) {
    if (!table && all[k].time > 1.0 + 1e-12) break;
    st.push_back(all[k]);
  }
  if (!(st.back().normal == st.front().normal) || st.back().target != st.front().target) {
    const double dt = st.size() > 1 ? st.back().time - st[st.size() - 2].time : 1.0;
    LoadStep close = st.front();
    close.time = st.back().time + dt;
    st.push_back(close);
  }
  const double t0 = st.front().time, T = st.back().time - t0;
  if (st.size() < 3 || !(T > 0.0))
    throw InputError("load.table: a wear run needs a period of at least two rows after the first");
  for (std::size_t k = 0; k < st.size(); ++k) {
    const Vec2 a = k > 0 ? Vec2(st[k].target - st[k - 1].target) : Vec2(Vec2::Zero());
    const Vec2 b = Vec2(k + 1 < st.size() ? st[k + 1].target : st[1].target) - st[k].target;
    st[k].turning = k > 0 && a.dot(b) < 0.0;
    st[k].time = (st[k].time - t0) / T;
  }
  st.back().time = 1.0;
  return st;
}

// The steps of a merged period (phases in (0, 1]) as a loop from phase `turn` through one
// period back to it.
std::vector<LoadStep> rotated(const std::vector<LoadStep>& cycle, double turn) {
  std::vector<LoadStep> out;
  for (const auto& ls : cycle)
    if (ls.time > turn) out.push_back(ls);
  for (const auto& ls : cycle)
    if (ls.time <= turn) {
      out.push_back(ls);
      out.back().time += 1.0;
    }
  return out;
}

// Whether the steady loop is periodic from its first pass: Coulomb friction with a fixed mu at
// a constant normal load without normal-tangential coupling, where the loop from the first
// turning point is closed (Masing; Mindlin & Deresiewicz 1953). Otherwise (a varying normal
// load, a friction law with memory, coupled pressures) the first pass after the virgin
// loading still carries its traction state, so the loop is run until it repeats.
bool loop_closes_at_once(const Model& model, const std::vector<LoadStep>& period) {
  for (const auto& ls : period)
    if (!(ls.normal == period.front().normal)) return false;
  return !model.friction->evolves() && !model.half_space->cross_coupled();
}

}  // namespace

WearCycles::WearCycles(Model& model, Stepper& stepper, std::vector<Observer*> observers)
    : model_(model), stepper_(stepper), observers_(std::move(observers)) {
  const PathType type = model.scenario.load.path;
  if (type != PathType::sine && type != PathType::table)
    throw InputError(
        "wear.law: a wear run needs a periodic load (load.path = sine, or table: one period)");
  initial_ = model.path.steps.front();
  const std::vector<LoadStep> period = one_period(model.scenario, model.path);
  cycle_ = merged(period);
  // The virgin loading: from the period's start to its first turning point; a period without
  // a reversal (only the normal load varies) to its end.
  std::vector<LoadStep> virgin{period.front()};
  for (std::size_t k = 1; k < period.size(); ++k) {
    virgin.push_back(period[k]);
    if (period[k].turning) break;
  }
  turn_ = virgin.back().time;
  virgin_ = merged(virgin);
  if (period.front().target != initial_.target) virgin_.insert(virgin_.begin(), period.front());
  // The steady loop: from the first turning point through one period back to it.
  std::vector<LoadStep> loop(virgin.end() - 1, virgin.end());
  for (const auto& ls : period)
    if (ls.time > turn_) loop.push_back(ls);
  for (std::size_t k = 1; k < virgin.size(); ++k) {
    loop.push_back(virgin[k]);
    loop.back().time += 1.0;
  }
  steady_ = merged(loop);
  settles_ = !loop_closes_at_once(model, period);
  // A loop that is run until it repeats takes the carried cycle's steps (the period's end
  // kept), so that it settles on the carried cycles' periodic state: a friction law with
  // memory depends on the steps (static/kinetic, sine at n = 32: a loop without the period's
  // end wore 29 % more than cycle mode's periodic cycle).
  if (settles_) steady_ = rotated(cycle_, turn_);
  carries_loop_ = settles_ && model.half_space->cross_coupled();
  repeats_ =
      model.half_space->cross_coupled() && model.scenario.solver.predictor != PredictorMode::none;
  // Masing's image needs the virgin curve from the traction-free state to the turning point:
  // one monotone step (merged), and tractions collinear with the load.
  masing_ = !settles_ && virgin_.size() == 1 && model.tangential_operator->components() == 1;
  turning_a_ = &virgin_.back();
  // The period's end is not a turning point for the carried cycles' field output.
  cycle_.back().turning = false;
}

const Communicator& WearCycles::comm() const {
  return model_.half_space->communicator();
}

double WearCycles::volume(const Field& worn) const {
  return comm().sum(worn.sum()) * model_.scenario.grid.cell_area();
}

// Over the grid's ranks; -inf for an empty slab.
double WearCycles::largest(const Field& x) const {
  return comm().max(x.size() ? x.maxCoeff() : -HUGE_VAL);
}

// The model's surfaces are the whole grid on every rank (the scenario's input, and what
// result.h5 and the checkpoint hold); worn depths are this rank's slab.
void WearCycles::wear_to(const Field& worn) {
  model_.surface = model_.surface0 - on_every_rank(*model_.half_space, worn);
}

Field WearCycles::worn() const {
  return slab_of(*model_.half_space, model_.surface0 - model_.surface);
}

void WearCycles::start() {
  step(initial_, 0.0, true);
}

StepRecord WearCycles::step(const LoadStep& ls, double time, bool emit) {
  const bool initial = &ls == &initial_;
  StepRecord rec = stepper_.advance(ls, initial ? 0 : 1, start_of(ls));
  rec.step = row_;
  rec.time = time;
  rec.cycle = int(std::floor(time + 1e-12));
  if (!emit) return rec;
  ++row_;
  for (auto* o : observers_) o->on_step(rec, stepper_.state(), model_);
  return rec;
}

// The state of an evaluation's start: traction-free on surface z0 - worn, the normal solve
// warm-started from `pressure` (empty: cold, from a uniform pressure). The pressure only
// starts the iteration, which runs to solver.tolerance, so the wear map moves with the start
// within that tolerance; from a far start (a worn conforming annulus, thousands of nodes at
// p < 1e-3 p_max) the normal solver restarts itself cold on stagnation (normal_solver.cpp).
// Under solver.coupling = coupled the pressure at a step's start also sets the tangential
// displacement it carries into that step, so there the start stays cold.
void WearCycles::fresh(const Field& worn, const Field& pressure) {
  traction_a_.clear(), reversed_a_.clear(), superposed_.clear();
  wear_to(worn);
  InterfaceState s = InterfaceState::zeros(*model_.tangential_operator);
  s.wear = worn;
  StepperMemory m = stepper_.memory();
  m.last_normal.reset();  // forces the normal re-solve on the new surface
  m.last_target.resize(0);
  m.fields.clear();  // the bound and the pressure's slip follow from the zero state
  const bool shaped = pressure.rows() == s.pressure.rows() && pressure.cols() == s.pressure.cols();
  if (shaped && pressure.allFinite() && !model_.half_space->cross_coupled()) {
    model_.friction->bound(s, m.fields["bound"]);  // the traction-free state's, as cold
    s.pressure = pressure;
  }
  m.wear_volume = volume(worn);
  stepper_.restore(s, m);
}

// Under solver.coupling = coupled (unless solver.predictor = none) each step of the carried
// cycle is a repeat slot of the stepper: its alternation starts from where the same step ended
// one cycle earlier (coupled_repeat.cpp).
WearCycle WearCycles::carried(double N) {
  WearCycle c = measure(N, cycle_, double(index_), repeats_);
  simulated_ += 1.0;
  c.simulated = simulated_;
  return c;
}

// The normal solve starts from the recent evaluations' pressures extrapolated to `worn`
// (WearWarmStart::start_for). On a loop that closes at once
// the virgin step starts from the Ciavarella–Jäger superposition (superpose_virgin) and the
// loop's steps at the turning loads from Masing's image of the first turning point. The image's
// slip is -2 times the virgin step's, so it meets the solver's stopping rule in one product
// when the virgin step's residual is at most half the tolerance, and is otherwise a start a
// few iterations from the answer (rough_fretting_wear.ini, n = 128: 1 and 7 products for the
// loop's two steps against 53 and 54 from the previous step's end).
WearCycle WearCycles::steady(double N, const Field& worn) {
  if (carries_loop_ && holds_loop_end_) return steady_from_last_loop(N, worn);
  fresh(worn, warm_.start_for(worn, comm()));
  stepper_.set_wear_cycle(N);  // named in a solver failure's message
  step(initial_, 0.0, false);
  warm_.remember(worn, stepper_.state().pressure);
  if (masing_) superpose_virgin();
  for (const auto& ls : virgin_) step(ls, 0.0, false);
  superposed_.clear();
  if (masing_) {
    const InterfaceState& s = stepper_.state();
    traction_a_ = s.traction;
    reversed_a_ = traction_a_;
    for (Field& t : reversed_a_) t = -t;
    warm_.corrective = (s.pressure - s.traction[0].abs() / model_.scenario.material.mu).max(0.0);
  }
  const int passes = settles_ ? settle() : 0;
  WearCycle c = measure(N, steady_, double(index_) - turn_);
  traction_a_.clear(), reversed_a_.clear();
  simulated_ += 1.0 + turn_ + passes;
  c.simulated = simulated_;
  holds_loop_end_ = true;
  return c;
}

// Under solver.coupling = coupled the loop approaches its periodic state slowly from the
// traction-free start: the loops' wear changed by 46-106 % from the first loop to the second,
// then by a factor 0.42 a loop (combination sweep seed 42 case 27), 0.51 (seed 46 case 11), or
// 0.7 rising to 0.88, like k^-2 (seed 45 case 45: the approach delta ratchets up by less each
// loop), so each evaluation settled in 10-11 loops. The periodic state of the last evaluated
// surface is a start within the surface's change: the same settle test then passes after 2-3
// loops (46/11, N = 40: 221.8 simulated cycles for 39 evaluations, 86.2 so; 45/45: 1053 and
// 337; 42/27: 486 and 146), the final worn depth within 1.1e-3 of the cold start's and no
// further from wear.integrator = cycle (docs/wear.md). The accumulated slip, dissipation and
// the bound they set restart as in a fresh start; the tractions, pressure and contact state
// are carried.
WearCycle WearCycles::steady_from_last_loop(double N, const Field& worn) {
  wear_to(worn);
  InterfaceState s = stepper_.state();
  s.wear = worn;
  for (Field& x : s.slip) x.setZero();
  s.slip_path.setZero();
  s.dissipation.setZero();
  StepperMemory m = stepper_.memory();
  m.last_normal.reset();    // forces the normal re-solve on the new surface
  m.fields.erase("bound");  // recomputed from the state
  m.wear_volume = volume(worn);
  stepper_.restore(s, m);
  stepper_.set_wear_cycle(N);  // named in a solver failure's message
  const int passes = settle();
  WearCycle c = measure(N, steady_, double(index_) - turn_);
  simulated_ += 1.0 + passes;
  c.simulated = simulated_;
  return c;
}

// The virgin step's start: tau = mu (p - p*), p* the normal solution at the load F_z - Q/mu
// (displacement control: at the approach delta - U/(mu E*/G*)), exact on the grid for a
// monotone loading from the traction-free state at constant normal load under the
// one-component analogy (contact/monotone_shortcut.hpp). Only a start: the incremental solve
// still runs to its stopping rule. Its corrective solve starts from the last evaluation's p*;
// when it fails the step starts from the traction-free state.
void WearCycles::superpose_virgin() {
  const InterfaceState& s = stepper_.state();
  const LoadStep& ls = *turning_a_;
  const double mu = model_.scenario.material.mu;
  const double ratio = model_.half_space->tangential_ratio();
  const Vec2 e = model_.tangential_operator->direction();
  // Approach from the worn surface's first touch (the state's is against the unworn datum).
  const double delta = s.indentation - (model_.surface0.maxCoeff() - model_.surface.maxCoeff());
  const Field& c = warm_.corrective;
  const bool shaped = c.rows() == s.pressure.rows() && c.cols() == s.pressure.cols();
  const Field* start = shaped ? &c : nullptr;
  const bool force = ls.control == Control::force;
  const double target = e.dot(ls.target * (force && ls.relative ? mu * s.normal_force : 1.0));
  const Field z = slab_of(*model_.half_space, model_.surface);  // the normal solver's slab
  try {
    const ShortcutResult r =
        force ? ciavarella_jaeger_force(*model_.normal, z, s.pressure, s.normal_force, delta, mu,
                                        ratio, std::abs(target), start)
              : ciavarella_jaeger_shift(*model_.normal, z, s.pressure, delta, mu, ratio,
                                        std::abs(target), start);
    superposed_ = {(target < 0.0 ? -1.0 : 1.0) * r.traction};
  } catch (const SolverError&) {
    superposed_.clear();
  }
}

// The start of a step of steady() (null: the previous step's end): the superposition for the
// virgin step, Masing's image for the loop's steps at +-Q_A (relative 1e-12: the sine's
// turning loads are +-amplitude to round-off).
const VecField* WearCycles::start_of(const LoadStep& ls) const {
  if (&ls == turning_a_ && !superposed_.empty()) return &superposed_;
  if (traction_a_.empty() || ls.control != turning_a_->control ||
      ls.relative != turning_a_->relative)
    return nullptr;
  const Vec2 a = turning_a_->target;
  const double tol = 1e-12 * a.norm();
  if ((ls.target - a).norm() <= tol) return &traction_a_;
  if ((ls.target + a).norm() <= tol) return &reversed_a_;
  return nullptr;
}

// Loops of the steady cycle, not emitted, until two in a row wear the same: the state at the
// loop's start is then the periodic one, which the measured loop starts from. Under the table
// F_z 10/12/10/8/10 N, F_x 0/3/0/-2/0 N (sphere, n = 64) the first loop after the virgin
// loading dissipated 4.305e-8 J and every later one 4.034e-8 J, the carried cycles' value.
// Returns the loops run.
int WearCycles::settle() {
  const WearSpec& w = model_.scenario.wear;
  const double tol =
      std::max(kSettleShare * w.rtol, kSettleNoise * model_.scenario.solver.tolerance);
  Field previous = loop_wear();
  double change = INFINITY;
  for (int k = 2; k <= kMaxSettleLoops; ++k) {
    Field rate = loop_wear();
    const double difference = largest((rate - previous).abs());
    const double scale = largest(rate.abs());
    if (difference <= tol * scale) return k;  // also two loops that wear nothing
    change = difference / scale;
    previous.swap(rate);
  }
  throw InputError("wear.integrator: the steady cycle of this load path did not repeat within " +
                   std::to_string(kMaxSettleLoops) + " periods (its wear still changed by " +
                   format_printf("%.3g", change) +
                   " of its maximum), so the ODE's wear map is not defined; use "
                   "wear.integrator = cycle");
}

// Worn depth of one silent loop of the steady cycle from the stepper's state (m).
Field WearCycles::loop_wear() {
  const Field wear0 = stepper_.state().wear;
  for (const auto& ls : steady_) step(ls, 0.0, false);
  return stepper_.state().wear - wear0;
}

WearCycle WearCycles::continued(double N) {
  WearCycle c = measure(N, steady_, double(index_) - turn_);
  holds_loop_end_ = true;
  simulated_ += 1.0;
  c.simulated = simulated_;
  return c;
}

double WearCycles::initial_indentation() {
  return probe_loading(model_.half_space->local_zeros()).indentation;
}

void WearCycles::resume(const WearCounters& c, const WearWarmStart& warm) {
  warm_ = warm;
  simulated_ = c.simulated;
  evaluations_ = c.evaluations;
  row_ = c.rows;
  index_ = c.index;
  stepper_.surface_changed();
  // The checkpoint's state is the end of the last loop (the probes leave it in place).
  holds_loop_end_ = true;
}

Field WearCycles::pressure_on(const Field& worn) {
  return probe_loading(worn).pressure;
}

// The probe is no part of the simulated history, but under solver.coupling = coupled its
// normal loading slips (the pressure moves the surfaces tangentially) and does work. Counted,
// that work entered the cumulative dissipation once more in a resumed run, which probes the
// indentation again: 4.0e-10 J (2.1e-4 relative) above the uninterrupted run from the first
// resumed row on (combination sweep seed 1 case 274). The stepper and the surface are put back
// as they were: a coupled run's next evaluation starts from the loop's end they hold
// (steady_from_last_loop), and a checkpoint written after a snapshot's probe holds it too.
InterfaceState WearCycles::probe_loading(const Field& worn) {
  const InterfaceState before = stepper_.state();
  const StepperMemory memory = stepper_.memory();
  const Field surface = model_.surface;
  fresh(worn, warm_.pressure);
  step(initial_, 0.0, false);
  InterfaceState probed = stepper_.state();
  model_.surface = surface;
  stepper_.restore(before, memory);
  return probed;
}

void WearCycles::apply(const Field& rate) {
  // The next cycle's normal solve is warm-started from this cycle's pressure (the tractions
  // are carried): the normal solver restarts itself when nodes leave contact in bulk and falls
  // back to a cold start on stagnation.
  model_.surface -= on_every_rank(*model_.half_space, rate);
  stepper_.surface_changed();
}

// Runs `steps` (row times shifted by t_shift) and measures the cycle (CycleMeter,
// history/cycle_summary.hpp): its worn depth is the growth of the stepper's worn-depth field
// over these steps.
WearCycle WearCycles::measure(double N, const std::vector<LoadStep>& steps, double t_shift,
                              bool repeat) {
  const InterfaceState& s = stepper_.state();
  const Field wear0 = s.wear;
  const Field worn = this->worn();
  CycleMeter meter(stepper_.memory().dissipation, s.slip_path, comm());
  stepper_.set_wear_cycle(N);  // named in a solver failure's message
  for (std::size_t k = 0; k < steps.size(); ++k) {
    stepper_.set_repeat_slot(repeat ? int(k) : -1);
    meter.add(step(steps[k], steps[k].time + t_shift, true), s, steps[k].time);
  }
  stepper_.set_repeat_slot(-1);
  const CycleMeasures m = meter.finish(stepper_.memory().dissipation, s);
  WearCycle c;
  c.N = N;
  c.rate = s.wear - wear0;
  c.energy = m.energy;
  c.wear_volume = volume(worn);
  c.max_depth = largest(worn);
  c.contact_radius = m.contact_radius;
  c.stick_area = m.stick_area;
  c.peak_pressure = m.peak_pressure;
  c.delta = m.delta;
  c.max_slip = m.max_slip;
  ++index_;
  ++evaluations_;
  return c;
}

}  // namespace fretbem
