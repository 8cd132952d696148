// Calibrated cost estimate of a stepped run (see cost_estimate.hpp).
#include "fretbem/history/cost_estimate.hpp"

#include <chrono>
#include <cstdio>

#include "fretbem/core/format.hpp"
#include "fretbem/core/progress.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/history/stepper.hpp"

namespace fretbem {

namespace {

using Clock = std::chrono::steady_clock;

std::string num(double v, const char* fmt = "%.2g") {
  return format_printf(fmt, v);
}

}  // namespace

RunCostEstimate estimate_run_cost(const Scenario& sc) {
  RunCostEstimate e;
  const auto t0 = Clock::now();
  auto model = build_model(sc);
  Stepper stepper(*model);
  const std::size_t steps = stepper.steps();
  // Wall time and convolutions of the solves alone (the operators' set-up excluded).
  double solve_seconds = 0.0, convolutions = 0.0, tangential = 0.0;
  auto timed = [&](std::size_t k) {
    const auto t = Clock::now();
    const StepRecord r = stepper.advance(k);
    solve_seconds += seconds_since(t);
    convolutions += r.convolutions;
    return double(r.convolutions);
  };
  const double step0 = timed(0);
  std::size_t k = 1;
  for (; k < steps && int(k) <= kCalibrationSteps; ++k) {
    tangential += timed(k);
    if (seconds_since(t0) > kCalibrationSeconds) {
      ++k;
      break;
    }
  }
  const std::size_t calibrated = k - 1;  // tangential steps solved
  e.calibration_steps = int(k);
  const double per_step = calibrated > 0 ? tangential / double(calibrated) : 0.0;
  e.convolutions = step0 + tangential + per_step * double(steps - k);
  e.seconds = convolutions > 0 ? e.convolutions * solve_seconds / convolutions : solve_seconds;
  e.calibration_seconds = seconds_since(t0);
  return e;
}

std::string describe(const RunCostEstimate& e, std::size_t steps) {
  return "  cost: about " + num(e.convolutions, "%.3g") + " FFT convolutions, " + num(e.seconds) +
         " s (from " + std::to_string(e.calibration_steps) + " of " + std::to_string(steps) +
         " steps solved in " + num(e.calibration_seconds) + " s; outputs not counted)\n";
}

}  // namespace fretbem
