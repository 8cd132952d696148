// Step doubling on the rows whose normal load changes: one step against two half steps from
// the same start state, halving while their difference exceeds load.tolerance x the row's
// share of a period. The allowance is the row's at every depth: where the slip zone stops
// within a step the estimate falls 4-10x per halving (second order), so a per-sub-step share
// (halved with the sub-step) refined to the depth limit for errors 6x below the asked one.
#include "fretbem/history/step_control.hpp"

#include <algorithm>
#include <cmath>

#include "fretbem/core/format.hpp"
#include "fretbem/core/input_warning.hpp"
#include "fretbem/history/stepper.hpp"

namespace fretbem {

bool bound_moves_within(const LoadStep& a, const LoadStep& b) {
  return a.normal.force_control == b.normal.force_control && a.normal.value != b.normal.value &&
         a.control == b.control && a.relative == b.relative;
}

LoadStep interpolate_load(const LoadStep& a, const LoadStep& b, double theta) {
  LoadStep s = b;
  s.time = a.time + theta * (b.time - a.time);
  s.cycle = cycle_of_time(s.time);
  s.normal.value = a.normal.value + theta * (b.normal.value - a.normal.value);
  s.target = a.target + theta * (b.target - a.target);
  s.turning = false;
  return s;
}

double step_error(const StepEnd& one, const StepEnd& two, const StepScales& scales) {
  auto relative = [](double difference, double scale) {
    return scale > 0.0 ? difference / scale : 0.0;
  };
  return std::max({relative(std::abs(one.dissipation_increment - two.dissipation_increment),
                            scales.dissipation),
                   relative((one.force - two.force).norm(), scales.force),
                   relative((one.shift - two.shift).norm(), scales.shift)});
}

namespace {

StepEnd end_of(const StepRecord& r, double dissipation_start) {
  return {r.dissipation - dissipation_start, {r.Fx, r.Fy}, {r.Ux, r.Uy}};
}

}  // namespace

Stepper::Snapshot Stepper::snapshot() const {
  return {state_,       bound_,       bound_start_,  pressure_start_, indentation_start_,
          dissipation_, wear_volume_, load_moved_,   bound_moved_,    surface_changed_,
          last_normal_, last_target_, pressure_slip_};
}

void Stepper::restore_snapshot(const Snapshot& s) {
  state_ = s.state;
  bound_ = s.bound, bound_start_ = s.bound_start, pressure_start_ = s.pressure_start;
  indentation_start_ = s.indentation_start;
  dissipation_ = s.dissipation, wear_volume_ = s.wear_volume;
  load_moved_ = s.load_moved, bound_moved_ = s.bound_moved, surface_changed_ = s.surface_changed;
  last_normal_ = s.last_normal;
  last_target_ = s.last_target;
  pressure_slip_ = s.pressure_slip;
}

// Row k by step doubling. The row's record is that of its last sub-step, with the work of every
// solve (accepted or not) in its iteration and convolution counts and the summed estimates in
// step_error.
StepRecord Stepper::advance_controlled(std::size_t k) {
  const LoadStep& a = model_.path.steps.at(k - 1);
  const LoadStep& b = model_.path.steps.at(k);
  if (!bound_moves_within(a, b)) return advance(b, int(k));
  HalfSpace& hs = *model_.half_space;
  const auto conv0 = hs.convolutions();
  row_guess_ = guess_, row_time_ = b.time, row_span_ = b.time - a.time;
  substep_normal_iterations_ = substep_tangential_iterations_ = substep_coupling_iterations_ = 0;
  substep_ = true;
  const Snapshot start = snapshot();
  StepRecord last = substep(b, int(k));
  const StepEnd one = end_of(last, start.dissipation);
  const double error = refine(start, a, b, one, 1, int(k), last);
  substep_ = false;
  guess_ = row_guess_;
  if (stiffness_wanted(model_, int(k), b.turning))
    last.kx = model_.stiffness->solve(state_.state).kx;
  last.normal_iterations = substep_normal_iterations_;
  last.tangential_iterations = substep_tangential_iterations_;
  last.coupling_iterations = substep_coupling_iterations_;
  last.convolutions = int(hs.convolutions() - conv0);
  last.step_error = error;
  return last;
}

// One solve of a sub-step; the row's predictor only for sub-steps that end at the row's load.
StepRecord Stepper::substep(const LoadStep& ls, int k) {
  guess_ = ls.time == row_time_ ? row_guess_ : nullptr;
  const StepRecord r = advance(ls, k);
  substep_normal_iterations_ += r.normal_iterations;
  substep_tangential_iterations_ += r.tangential_iterations;
  substep_coupling_iterations_ += r.coupling_iterations;
  return r;
}

// From `start` (the state at a) over [a, b], whose single step ended at `one`: two half steps,
// kept when they agree with it, else each half refined the same way. Leaves the state at b and
// `last` the record of the last sub-step; returns the sum of the kept estimates.
double Stepper::refine(const Snapshot& start, const LoadStep& a, const LoadStep& b,
                       const StepEnd& one, int depth, int k, StepRecord& last) {
  restore_snapshot(start);
  const LoadStep mid = interpolate_load(a, b, 0.5);
  const StepEnd left = end_of(substep(mid, k), start.dissipation);
  last = substep(b, k);
  const double error = step_error(one, end_of(last, start.dissipation),
                                  step_scales(b.time, one, end_of(last, start.dissipation)));
  const double allowed = model_.scenario.load.tolerance * row_span_;
  if (error <= allowed) return error;
  if (depth >= kMaxStepDepth) {
    if (!depth_limit_said_)
      input_warning("load.tolerance = " + format_number(model_.scenario.load.tolerance) +
                    ": step " + std::to_string(k) + " keeps an estimated error of " +
                    format_number(error) + " (allowed " + format_number(allowed) + ") after " +
                    std::to_string(1 << kMaxStepDepth) +
                    " sub-steps (the limit); step_error reports every such step");
    depth_limit_said_ = true;
    return error;
  }
  double sum = refine(start, a, mid, left, depth + 1, k, last);
  const Snapshot left_end = snapshot();
  const StepEnd right = end_of(substep(b, k), left_end.dissipation);
  sum += refine(left_end, mid, b, right, depth + 1, k, last);
  return sum;
}

// The mean dissipation per period so far, and the largest |F| and |U| of the rows so far and of
// this step's two ends.
StepScales Stepper::step_scales(double t_end, const StepEnd& one, const StepEnd& two) const {
  const double periods = t_end - model_.path.steps.front().time;
  StepScales s;
  s.dissipation = std::max({dissipation_ / periods, std::abs(one.dissipation_increment),
                            std::abs(two.dissipation_increment)});
  s.force = std::max({force_scale_, one.force.norm(), two.force.norm()});
  s.shift = std::max({shift_scale_, one.shift.norm(), two.shift.norm()});
  return s;
}

void Stepper::update_step_scales(const StepRecord& rec) {
  force_scale_ = std::max(force_scale_, std::hypot(rec.Fx, rec.Fy));
  shift_scale_ = std::max(shift_scale_, std::hypot(rec.Ux, rec.Uy));
}

}  // namespace fretbem
