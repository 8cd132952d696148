// What a run will cost, before it runs (`fretbem check`, issue 19): the first steps of the
// load path are solved at the scenario's grid (a calibration), their FFT convolutions per step
// and wall seconds per convolution are extrapolated to the whole path.
#pragma once

#include <string>

#include "fretbem/scenario/scenario.hpp"

namespace fretbem {

struct RunCostEstimate {
  double convolutions = 0.0;         ///< predicted FFT convolutions of the whole run
  double seconds = 0.0;              ///< predicted wall time of the solves (s), outputs excluded
  int calibration_steps = 0;         ///< steps solved to calibrate (step 0 included)
  double calibration_seconds = 0.0;  ///< wall time of the calibration, operators built (s)
};

/// Calibration budget: step 0 (the normal loading), then tangential steps until
/// kCalibrationSteps of them ran or the calibration took kCalibrationSeconds (at least one).
inline constexpr int kCalibrationSteps = 4;
inline constexpr double kCalibrationSeconds = 1.0;

/// Builds the model (operators included), solves the first steps and extrapolates: the
/// convolutions of step 0 plus the mean of the calibrated tangential steps times the steps
/// left; seconds = convolutions x the calibration's wall seconds per convolution. Writes no
/// file. Not for wear runs (estimate_wear_cost).
RunCostEstimate estimate_run_cost(const Scenario& sc);

/// The report line(s) of `fretbem check`, each ending in '\n'.
std::string describe(const RunCostEstimate& e, std::size_t steps);

}  // namespace fretbem
