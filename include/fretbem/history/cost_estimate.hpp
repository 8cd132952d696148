// What a run will cost, before it runs (`fretbem check`): the first steps of the
// load path are solved at the scenario's grid (a calibration), their FFT convolutions per step
// and CPU seconds per convolution are extrapolated to the whole path. Measured accuracy:
// docs/reliability.md ("Accuracy of check's cost estimate").
#pragma once

#include <string>
#include <vector>

#include "fretbem/history/model.hpp"
#include "fretbem/scenario/scenario.hpp"

namespace fretbem {

struct RunCostEstimate {
  double convolutions = 0.0;         ///< predicted FFT convolutions of the whole run
  double seconds = 0.0;              ///< predicted CPU time of the solves (s), outputs excluded
  int calibration_steps = 0;         ///< steps solved to calibrate (step 0 included)
  double calibration_seconds = 0.0;  ///< CPU time of the calibration, operators built (s)
};

/// Calibration budget: step 0 (the normal loading), then tangential steps until
/// kCalibrationSteps of them ran or the calibration took kCalibrationSeconds of CPU (at least
/// one).
inline constexpr int kCalibrationSteps = 4;
inline constexpr double kCalibrationSeconds = 1.0;

/// Cost of a tangential step after the path's second turning point (the first reversal
/// completed) relative to the first steps: the later half-cycles start from the stick set of
/// the previous one in the same direction. Measured steady/first-step convolution ratios:
/// 0.45 (Mindlin n = 64), 0.53 (n = 128), 0.59 (rough cycle n = 128), docs/reliability.md.
inline constexpr double kSettledStepShare = 0.5;
/// Cost of a step the cycle predictor starts (Model::cycle_predictor, a load transition seen
/// before) relative to the first steps: such a step usually meets the tolerance from its start
/// and costs one product. bench_cycle n = 256: 72 convolutions in cycle 2 and 64-76 from cycle 3
/// on against ~20 per first step (64 steps): 0.05-0.06; the shipped cyclic scenarios at n = 32
/// and the n = 64 Mindlin loop's ETA (test_cost_estimate) put the mean near 0.04.
inline constexpr double kPredictedStepShare = 0.04;

/// Each step's cost relative to a first tangential step (step 0 counts 1 too): 1 up to the
/// path's second turning point, kSettledStepShare after it, kPredictedStepShare where the
/// cycle predictor starts the step; a step the Masing image starts counts kSettledStepShare
/// before the second turning point and kPredictedStepShare after it. What the estimate extrapolates
/// with and what a run's progress ETA counts on.
std::vector<double> step_cost_shares(const Model& model);

/// Builds the model (operators included), solves the first steps and extrapolates: the
/// convolutions of step 0 plus the mean of the calibrated tangential steps times the steps
/// left (those past the second turning point at kSettledStepShare); seconds = convolutions x
/// the calibration's CPU seconds per convolution. Writes no file. Not for wear runs
/// (estimate_wear_cost).
RunCostEstimate estimate_run_cost(const Scenario& sc);

/// The report line(s) of `fretbem check`, each ending in '\n'.
std::string describe(const RunCostEstimate& e, std::size_t steps);

}  // namespace fretbem
