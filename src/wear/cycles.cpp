// WearCycles: simulated cycles of the scenario's load path on a frozen surface (see
// wear_integrator.hpp for why the surface changes only between cycles).
#include <cmath>
#include <numbers>

#include "fretbem/core/errors.hpp"
#include "fretbem/wear/integrator.hpp"

namespace fretbem {

WearCycles::WearCycles(Model& model, Stepper& stepper, std::vector<Observer*> observers)
    : model_(model), stepper_(stepper), observers_(std::move(observers)) {
  if (model.scenario.load.path != PathType::sine)
    throw InputError("wear.law: a wear run needs a cyclic load (load.path = sine)");
  const auto& steps = model.path.steps;
  initial_ = steps.front();
  // One period. Between turning points a sine load is monotone at constant normal load, where
  // the incremental solution does not depend on the step size and each node slips one way
  // (Ciavarella–Jäger), so sum |s| over a segment is exact in one step: only the turning
  // points (and the period's end, for the carried cycles) are kept (DESIGN §2 "one big
  // increment").
  // (The path's last step is flagged turning for the field output; it is the period's end.)
  for (std::size_t k = 1; k < steps.size() && steps[k].time <= 1.0 + 1e-12; ++k) {
    const bool end = std::abs(steps[k].time - 1.0) < 1e-12;
    if (steps[k].turning || end) cycle_.push_back(steps[k]);
    if (end) cycle_.back().turning = false;
  }
  turn_ = -1.0;
  for (const auto& ls : cycle_) {
    if (turn_ < 0.0) virgin_.push_back(ls);
    if (turn_ < 0.0 && ls.turning) turn_ = ls.time;
  }
  if (turn_ <= 0.0 || turn_ >= 1.0) throw InputError("load.path: no turning point in a cycle");
  // The steady loop: from the first turning point through one period back to it.
  for (const auto& ls : cycle_)
    if (ls.time > turn_ && ls.turning) steady_.push_back(ls);
  LoadStep back = virgin_.back();
  back.time += 1.0;
  steady_.push_back(back);
}

void WearCycles::start() {
  step(initial_, 0.0, true);
}

StepRecord WearCycles::step(const LoadStep& ls, double time, bool emit) {
  const bool initial = &ls == &initial_;
  StepRecord rec = stepper_.advance(ls, initial ? 0 : 1);
  rec.step = row_;
  rec.time = time;
  rec.cycle = int(std::floor(time + 1e-12));
  if (!emit) return rec;
  ++row_;
  for (auto* o : observers_) o->on_step(rec, stepper_.state(), model_);
  return rec;
}

void WearCycles::fresh(const Field& worn) {
  model_.surface = model_.surface0 - worn;
  InterfaceState s = InterfaceState::zeros(*model_.tangential_operator);
  s.pressure = stepper_.state().pressure;  // warm start of the normal solve only
  s.wear = worn;
  StepperMemory m = stepper_.memory();
  m.last_normal.reset();  // forces the normal re-solve on the new surface
  m.last_target.resize(0);
  m.wear_volume = worn.sum() * model_.scenario.grid.cell_area();
  stepper_.restore(s, m);
}

WearCycle WearCycles::carried(double N) {
  WearCycle c = measure(N, cycle_, double(index_));
  simulated_ += 1.0;
  c.simulated = simulated_;
  return c;
}

WearCycle WearCycles::steady(double N, const Field& worn) {
  fresh(worn);
  step(initial_, 0.0, false);
  for (const auto& ls : virgin_) step(ls, 0.0, false);
  WearCycle c = measure(N, steady_, double(index_) - turn_);
  simulated_ += 1.0 + turn_;
  c.simulated = simulated_;
  return c;
}

void WearCycles::resume(const WearCounters& c) {
  simulated_ = c.simulated;
  evaluations_ = c.evaluations;
  row_ = c.rows;
  index_ = c.index;
  stepper_.surface_changed();
}

Field WearCycles::pressure_on(const Field& worn) {
  fresh(worn);
  step(initial_, 0.0, false);
  return stepper_.state().pressure;
}

void WearCycles::apply(const Field& rate) {
  model_.surface -= rate;
  stepper_.surface_changed();
}

// Runs `steps` (row times shifted by t_shift) and measures the cycle: its worn depth is the
// growth of the stepper's worn-depth field over these steps.
WearCycle WearCycles::measure(double N, const std::vector<LoadStep>& steps, double t_shift) {
  const InterfaceState& s = stepper_.state();
  const Field wear0 = s.wear, path0 = s.slip_path;
  const Field worn = model_.surface0 - model_.surface;
  double diss0 = stepper_.memory().dissipation;
  stepper_.set_wear_cycle(N);  // named in a solver failure's message
  WearCycle c;
  c.N = N;
  c.stick_area = INFINITY;
  double contact = 0.0;
  for (const auto& ls : steps) {
    const StepRecord r = step(ls, ls.time + t_shift, true);
    c.stick_area = std::min(c.stick_area, r.stick_area);
    contact = r.contact_area;
    c.delta = r.delta;
  }
  c.rate = s.wear - wear0;
  c.energy = stepper_.memory().dissipation - diss0;
  c.wear_volume = worn.sum() * model_.scenario.grid.cell_area();
  c.max_depth = worn.maxCoeff();
  c.contact_radius = std::sqrt(contact / std::numbers::pi);
  c.peak_pressure = s.pressure.maxCoeff();
  // Stability of explicit steps involves only nodes in contact (a separated node neither
  // wears nor passes load on), so the largest slip is taken over them.
  c.max_slip = ((s.pressure > 0.0).cast<double>() * (s.slip_path - path0)).maxCoeff();
  ++index_;
  ++evaluations_;
  return c;
}

}  // namespace fretbem
