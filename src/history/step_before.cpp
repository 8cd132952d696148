// The step before, for the three-point rule of the moving bound (contact/step_work.hpp) on a
// table interpolated by its spline (load.interpolation = cubic): what the next step's
// quadrature reads of this one, kept from step to step and in the checkpoint. The rule needs
// the path C1 across both steps: both ends of each on the spline and no turning point between
// them (the slip reverses there). Not in wear runs (their cycles restore and replay rows on
// frozen surfaces, and book the trapezoid), coupled runs (the bound moves within the
// coupling's alternation) or under a friction law that evolves (the bound is not the normal
// load's alone).
#include <cmath>

#include "fretbem/history/stepper.hpp"

namespace fretbem {

bool Stepper::three_point_applies() const {
  return model_.scenario.load.interpolation == LoadInterpolation::cubic && !model_.wear &&
         !model_.half_space->cross_coupled() && !model_.friction->evolves();
}

// At the start of a step to ls: whether its end is on the spline, and its span.
void Stepper::begin_step_before(const LoadStep& ls) {
  step_on_spline_ = three_point_applies() && ls.rate.has_value();
  step_span_ = ls.time - last_time_;
  step_turning_ = ls.turning;
  step_booked_ = false;
}

// The step before as the quadrature reads it, where it joins this one on the spline.
std::optional<StepBefore> Stepper::step_before() const {
  const StepBeforeMemory& m = before_;
  if (!step_on_spline_ || !m.smooth || m.slip.size() != bound_.size()) return std::nullopt;
  return StepBefore{m.bound_change, m.pressure_change, m.slip, m.span, step_span_};
}

// After accumulate_slip booked this step (bound moved from bound_start_ when `before` holds
// the start states): its changes and the slip of the nodes that slipped at both its ends.
void Stepper::remember_step(const StateField* before) {
  step_booked_ = true;
  if (!step_on_spline_) return;
  StepBeforeMemory& m = before_;
  const bool moved = before && bound_start_.size() == bound_.size();
  m.smooth = moved && last_end_on_spline_ && !step_turning_;
  m.span = step_span_;
  if (!m.smooth) return;
  const auto slip = std::uint8_t(NodeState::slip);
  m.bound_change = bound_ - bound_start_;
  m.pressure_change = state_.pressure - pressure_start_;
  m.slip = ((*before == slip) && (state_.state == slip))
               .select(work_.slip, Field::Zero(bound_.rows(), bound_.cols()));
}

// At the end of a step to ls: a step that booked nothing (no increment) leaves no step before.
void Stepper::end_step_before(const LoadStep& ls) {
  if (!step_booked_) before_.smooth = false;
  last_end_on_spline_ = step_on_spline_;
  last_time_ = ls.time;
}

void Stepper::save_step_before(StepperMemory& m) const {
  if (!three_point_applies()) return;
  m.step_before = {before_.span, before_.smooth ? 1.0 : 0.0};
  if (!before_.smooth) return;
  m.fields["before_bound_change"] = before_.bound_change;
  m.fields["before_pressure_change"] = before_.pressure_change;
  m.fields["before_slip"] = before_.slip;
}

// Checkpoints are written between rows: the last step ended at row next_ - 1.
void Stepper::restore_step_before(const StepperMemory& m) {
  before_ = {};
  const std::vector<LoadStep>& steps = model_.path.steps;
  const LoadStep* last =
      m.next_step > 0 && m.next_step <= steps.size() ? &steps[m.next_step - 1] : nullptr;
  last_time_ = last ? last->time : 0.0;
  last_end_on_spline_ = last && three_point_applies() && last->rate.has_value();
  const auto dg = m.fields.find("before_bound_change"),
             dp = m.fields.find("before_pressure_change"), s = m.fields.find("before_slip");
  if (m.step_before.size() != 2 || !(m.step_before[1] > 0.0) || dg == m.fields.end() ||
      dp == m.fields.end() || s == m.fields.end())
    return;
  before_ = {dg->second, dp->second, s->second, m.step_before[0], true};
}

}  // namespace fretbem
