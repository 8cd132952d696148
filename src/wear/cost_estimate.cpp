// Calibrated cost estimate of a wear run (see cost_estimate.hpp).
#include "fretbem/wear/cost_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "fretbem/core/format.hpp"
#include "fretbem/core/progress.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/wear/integrator.hpp"

namespace fretbem {

namespace {

std::string num(double v, const char* fmt = "%.3g") {
  return format_printf(fmt, v);
}

// Lowest simulated-cycle count of the implicit integrator measured in docs/wear.md
// (n = 32, N = 2e4: 494); below it an estimate would be a guess.
constexpr double kImplicitMeasuredLow = 494.0;

// The explicit integrator's fewest simulated cycles: the first steady cycle, then for each
// interval between snapshots (where the integrator stops) at least ceil(length / cap)
// Heun-Euler steps of two steady-cycle evaluations each, or the interval's cycles one by one
// when those cost less (the run's cost guard).
double explicit_low(double N, double cap, double per_evaluation) {
  const auto snaps = snapshot_cycles(N);
  double low = per_evaluation;
  for (std::size_t i = 1; i < snaps.size(); ++i) {
    const double length = snaps[i] - snaps[i - 1];
    low += std::min(length, 2.0 * per_evaluation * std::ceil(length / cap));
  }
  return low;
}

}  // namespace

WearCostEstimate estimate_wear_cost(const Scenario& sc) {
  WearCostEstimate e;
  const double cpu0 = process_cpu_seconds();
  auto model = build_model(sc);
  Stepper stepper(*model);
  WearCycles cycles(*model, stepper);
  const double cpu1 = process_cpu_seconds();
  const auto conv0 = model->half_space->convolutions();
  cycles.start();
  const WearCycle c0 =
      cycles.steady(0.0, Field::Zero(model->scenario.grid.nx, model->scenario.grid.ny));
  const double seconds = process_cpu_seconds() - cpu1;
  const double conv = double(model->half_space->convolutions() - conv0);
  // Simulated cycles of one steady cycle (the ODE right-hand side): to the first turning point
  // from a traction-free state, then one period (docs/wear.md).
  const double per_evaluation = cycles.simulated();
  e.convolutions_per_cycle = conv / per_evaluation;
  e.seconds_per_cycle = seconds / per_evaluation;
  e.cap = explicit_step_cap(*model, c0.max_slip);
  const WearSpec& w = sc.wear;
  const double N = w.cycles;
  e.implicit = runs_implicit(w.integrator, N, e.cap, cycles.simulated());
  if (w.integrator == WearIntegrator::cycle) {
    e.simulated_low = e.simulated_high = N + 1.0;  // cycles 0..N, the last one observes
  } else if (e.implicit) {
    e.simulated_high = N + 1.0;
    e.simulated_low = std::min(e.simulated_high, kImplicitMeasuredLow);
  } else {
    e.simulated_low = std::min(N + 1.0, explicit_low(N, e.cap, per_evaluation));
    e.simulated_high = std::min(N + 1.0, kExplicitRangeFactor * e.simulated_low);
  }
  e.calibration_seconds = process_cpu_seconds() - cpu0;
  return e;
}

std::string describe(const WearCostEstimate& e, const WearSpec& w) {
  const char* method = w.integrator == WearIntegrator::cycle ? "cycle by cycle"
                       : e.implicit                          ? "implicit (dirk)"
                                                             : "explicit (erk)";
  // A cap of 10 cycles or more is a cycle count: printed whole ("1410", not "1.41e+03").
  const std::string cap = e.cap >= 10.0 ? format_count(std::round(e.cap)) : num(e.cap);
  std::string o = "  wear stability cap: " + cap +
                  " cycles per explicit step (wear.cycles = " + format_count(w.cycles) + " = " +
                  num(w.cycles / e.cap) + " caps): " + method + "\n";
  const std::string range = e.simulated_low == e.simulated_high
                                ? format_count(std::round(e.simulated_low))
                                : format_count(std::round(e.simulated_low)) + " to " +
                                      format_count(std::round(e.simulated_high));
  o += "  expected simulated cycles: " + range + "; each about " + num(e.convolutions_per_cycle) +
       " FFT convolutions, " + num(e.seconds_per_cycle, "%.2g") + " s\n";
  o += "  cost: about " + num(e.seconds_per_cycle * e.simulated_low, "%.2g") +
       (e.simulated_low == e.simulated_high
            ? std::string()
            : " to " + num(e.seconds_per_cycle * e.simulated_high, "%.2g")) +
       " s of CPU (from one steady cycle solved in " + num(e.calibration_seconds, "%.2g") + " s)\n";
  if (const std::string warn = explicit_cap_warning(w, e.cap); !warn.empty())
    o += "  " + warn + "\n";
  return o;
}

}  // namespace fretbem
