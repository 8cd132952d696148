// Calibrated cost estimate of a wear run (see cost_estimate.hpp).
#include "fretbem/wear/cost_estimate.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "fretbem/core/format.hpp"
#include "fretbem/core/progress.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/wear/integrator.hpp"

namespace fretbem {

namespace {

using Clock = std::chrono::steady_clock;

std::string num(double v, const char* fmt = "%.3g") {
  return format_printf(fmt, v);
}

// Simulated cycles of the steady cycle (the ODE right-hand side): to the first turning point
// from a traction-free state, then one period (docs/wear.md).
constexpr double kCyclesPerEvaluation = 1.25;
// Lowest simulated-cycle count of the implicit integrator measured in docs/wear.md
// (n = 32, N = 2e4: 494); below it an estimate would be a guess.
constexpr double kImplicitMeasuredLow = 494.0;

}  // namespace

WearCostEstimate estimate_wear_cost(const Scenario& sc) {
  WearCostEstimate e;
  const auto t0 = Clock::now();
  auto model = build_model(sc);
  Stepper stepper(*model);
  WearCycles cycles(*model, stepper);
  const auto t1 = Clock::now();
  const auto conv0 = model->half_space->convolutions();
  cycles.start();
  const WearCycle c0 =
      cycles.steady(0.0, Field::Zero(model->scenario.grid.nx, model->scenario.grid.ny));
  const double seconds = seconds_since(t1);
  const double conv = double(model->half_space->convolutions() - conv0);
  e.convolutions_per_cycle = conv / cycles.simulated();
  e.seconds_per_cycle = seconds / cycles.simulated();
  e.cap = explicit_step_cap(*model, c0.max_slip);
  const WearSpec& w = sc.wear;
  const double N = w.cycles;
  e.implicit = runs_implicit(w.integrator, N, e.cap, cycles.simulated());
  if (w.integrator == WearIntegrator::cycle) {
    e.simulated_low = e.simulated_high = N;
  } else if (e.implicit) {
    e.simulated_high = N + 1.0;
    e.simulated_low = std::min(e.simulated_high, kImplicitMeasuredLow);
  } else {
    e.simulated_high = N + 1.0;
    e.simulated_low =
        std::min(e.simulated_high, kCyclesPerEvaluation * (1.0 + 2.0 * std::ceil(N / e.cap)));
  }
  e.calibration_seconds = seconds_since(t0);
  return e;
}

std::string describe(const WearCostEstimate& e, const WearSpec& w) {
  const char* method = w.integrator == WearIntegrator::cycle ? "cycle by cycle"
                       : e.implicit                          ? "implicit (dirk)"
                                                             : "explicit (erk)";
  std::string o = "  wear stability cap: " + num(e.cap) +
                  " cycles per explicit step (wear.cycles = " + num(w.cycles, "%.6g") + " = " +
                  num(w.cycles / e.cap) + " caps): " + method + "\n";
  const std::string range =
      e.simulated_low == e.simulated_high
          ? num(e.simulated_low, "%.6g")
          : num(e.simulated_low, "%.6g") + " to " + num(e.simulated_high, "%.6g");
  o += "  expected simulated cycles: " + range + "; each about " + num(e.convolutions_per_cycle) +
       " FFT convolutions, " + num(e.seconds_per_cycle, "%.2g") + " s\n";
  o += "  cost: about " + num(e.seconds_per_cycle * e.simulated_low, "%.2g") +
       (e.simulated_low == e.simulated_high
            ? std::string()
            : " to " + num(e.seconds_per_cycle * e.simulated_high, "%.2g")) +
       " s (from one steady cycle solved in " + num(e.calibration_seconds, "%.2g") + " s)\n";
  if (const std::string warn = explicit_cap_warning(w, e.cap); !warn.empty())
    o += "  " + warn + "\n";
  return o;
}

}  // namespace fretbem
