// Error-controlled load steps (load.tolerance): where the normal load changes over a step, the
// Coulomb bound mu p moves within it and the increment depends on the step; the stepper then
// compares one step with two half steps (step doubling) and halves the step where they differ
// by more than the tolerance allows, down to kMaxStepDepth halvings. Sub-steps are internal: a
// row of the path stays one output row (docs/algorithms.md, "Error-controlled load steps").
#pragma once

#include "fretbem/contact/tangential_operator.hpp"
#include "fretbem/history/load_path.hpp"

namespace fretbem {

/// Halvings of a row at most: 2^8 = 256 sub-steps.
constexpr int kMaxStepDepth = 8;

/// Whether the bound can move within the step from a to b, so that the step's solution depends
/// on its length: the normal load changes (same control of the normal load and of the
/// tangential path at both ends). A constant normal load with a constant friction law gives
/// the same increment whatever the step, and is never subdivided.
bool bound_moves_within(const LoadStep& a, const LoadStep& b);

/// The load at fraction theta in [0, 1] of the step from a to b: time, normal load and
/// tangential target linear in theta (tables are linear between rows). Control and units are
/// b's; the interpolated load is no turning point.
LoadStep interpolate_load(const LoadStep& a, const LoadStep& b, double theta);

/// What step doubling compares at a step's end: the dissipation increment over the step (J)
/// and the tangential force (N) and shift (m) at its end.
struct StepEnd {
  double dissipation_increment = 0.0;
  Vec2 force{0.0, 0.0};
  Vec2 shift{0.0, 0.0};
};

/// The run's scales the differences are measured against: dissipation per period (J), and the
/// largest |F| (N) and |U| (m) so far. A zero scale drops its term.
struct StepScales {
  double dissipation = 0.0;
  double force = 0.0;
  double shift = 0.0;
};

/// The estimate of a step's error: the largest of |dD_1 - dD_2| / D, |F_1 - F_2| / F and
/// |U_1 - U_2| / U between one step (1) and two half steps (2) over the same interval.
double step_error(const StepEnd& one, const StepEnd& two, const StepScales& scales);

}  // namespace fretbem
