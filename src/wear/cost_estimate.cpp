// Calibrated cost estimate of a wear run on the run's cost model (history/cost_estimate.hpp):
// a warm steady cycle measured by its ConvolutionMeter, and the simulated cycles each integrator
// needs (see cost_estimate.hpp).
#include "fretbem/wear/cost_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "fretbem/core/format.hpp"
#include "fretbem/core/progress.hpp"
#include "fretbem/history/cost_estimate.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/wear/integrator.hpp"

namespace fretbem {

namespace {

std::string num(double v, const char* fmt = "%.3g") {
  return format_printf(fmt, v);
}

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

// The implicit integrator stops at every snapshot: at least one TR-BDF2 step per interval,
// about three steady-cycle evaluations, or the interval's cycles one by one when shorter.
double implicit_floor(double N, double per_evaluation) {
  const auto snaps = snapshot_cycles(N);
  double floor = per_evaluation;
  for (std::size_t i = 1; i < snaps.size(); ++i)
    floor += std::min(snaps[i] - snaps[i - 1], 3.0 * per_evaluation);
  return floor;
}

// Empirical model of the implicit integrator's simulated cycles. Its exponents are fitted to
// the 33 dirk/arkode runs of docs/wear.md (n = 32-128, Q = 0.3-0.95 muP, N = 5e4-1e7, Archard
// and energy laws): implicit_floor x kScale (a/h)^0.75 (A/A_stick)^1.125. The contact's size
// in cells a/h and the slip share set how many contact-set changes the Newton iterations meet
// (Q = 0.9 cost 3-4x Q = 0.3; n = 128 about twice n = 32). A sphere's A_stick/A =
// (1 - q)^(2/3), so the last factor is (1 - q)^-0.75; it is held at q = 0.95 (gross slip has
// no stick zone). The scale: Newton's first iterate of a stage is the step's start, answered
// without a cycle (wear_rhs), and the nine runs of docs/reliability.md ("Implicit (dirk) wear
// range") simulate 0.32-1.25 of the model at the scale 0.2 the 33 runs gave; 0.125 puts their
// geometric centre at 1, and the range kImplicitRange (0.51-2.0 of them) holds all nine.
double implicit_middle(double N, double per_evaluation, double a_over_h, double stick_share) {
  constexpr double kScale = 0.125, kSizeExponent = 0.75, kStickExponent = 1.125;
  constexpr double kLeastStickShare = 0.136;  // (1 - 0.95)^(2/3)
  return kScale * implicit_floor(N, per_evaluation) * std::pow(a_over_h, kSizeExponent) *
         std::pow(std::max(stick_share, kLeastStickShare), -kStickExponent);
}
constexpr double kImplicitRange[2] = {0.45, 2.5};

// The wear of the ODE integrators' first step, in cycles: the first step ARKODE tries
// (arkode_stepper.cpp, create: the stability cap, or a hundredth of the run).
double first_step(const WearSpec& w, double cap) {
  return std::min({cap, w.cycles, std::max(1.0, 0.01 * w.cycles)});
}

}  // namespace

double SimulatedCycles::middle() const {
  return std::sqrt(low * high);
}

SimulatedCycles expected_simulated_cycles(const Scenario& sc, bool implicit, double cap,
                                          double per_evaluation, const WearCycle& c0) {
  const double N = sc.wear.cycles, most = N + 1.0;  // cycles 0..N, the last one observes
  if (sc.wear.integrator == WearIntegrator::cycle) return {most, most};
  if (!implicit) {
    const double low = std::min(most, explicit_low(N, cap, per_evaluation));
    return {low, std::min(most, kExplicitRangeFactor * low)};
  }
  const double area = M_PI * c0.contact_radius * c0.contact_radius;
  const double stick_share = area > 0.0 ? c0.stick_area / area : 1.0;
  const double middle =
      implicit_middle(N, per_evaluation, c0.contact_radius / sc.grid.h, stick_share);
  return {std::min(most, kImplicitRange[0] * middle), std::min(most, kImplicitRange[1] * middle)};
}

namespace {

// What a calibration measured: the first cycle (its slip sets the stability cap) and the
// simulated cycles of one wear-map evaluation (1 in cycle mode).
struct Calibrated {
  WearCycle first;
  double per_evaluation = 1.0;
};

// Cycle mode: the cycles the run simulates, each carried from the last one's end on the
// surface the last one wore (under `coupled` each step from the same step one cycle earlier),
// calibrated on the third. Their loop need not repeat (an evolving mu drifts cycle by cycle, so
// steady() would not settle), and the run never asks it to.
Calibrated calibrate_carried(WearCycles& cycles, const Model& model, WearCostEstimate& e) {
  cycles.start();
  Calibrated c{cycles.carried(0.0)};
  cycles.apply(c.first.rate);
  e.cap = explicit_step_cap(model, c.first.max_slip);
  cycles.apply(cycles.carried(1.0).rate);
  const ConvolutionMeter meter(*model.half_space);
  const double simulated0 = cycles.simulated();
  cycles.carried(2.0);
  const double measured = cycles.simulated() - simulated0;
  e.convolutions_per_cycle = meter.convolutions() / measured;
  e.seconds_per_cycle = meter.seconds() / measured;
  return c;
}

// The ODE integrators: the steady cycle of the unworn surface, then, as the run's evaluations
// start from the previous evaluation's solves (docs/wear.md, "Where an evaluation's solves
// start") and the cold first one costs 2-3 times more, the second evaluation, on the surface
// worn by the run's first step, is the one calibrated on.
Calibrated calibrate_steady(WearCycles& cycles, const Model& model, WearCostEstimate& e) {
  const WearSpec& w = model.scenario.wear;
  cycles.start();
  Calibrated c{cycles.steady(0.0, model.half_space->local_zeros())};
  e.cap = explicit_step_cap(model, c.first.max_slip);
  require_ode_cap(w, e.cap);
  const ConvolutionMeter meter(*model.half_space);
  const double simulated0 = cycles.simulated();
  cycles.steady(0.0, c.first.rate * first_step(w, e.cap));
  // Simulated cycles of one steady cycle (the ODE right-hand side): to the first turning point
  // from a traction-free state, then one period (docs/wear.md).
  c.per_evaluation = cycles.simulated() - simulated0;
  e.convolutions_per_cycle = kWarmCostFactor * meter.convolutions() / c.per_evaluation;
  e.seconds_per_cycle = kWarmCostFactor * meter.seconds() / c.per_evaluation;
  e.implicit = runs_implicit(w.integrator, w.cycles, e.cap, cycles.simulated());
  return c;
}

}  // namespace

WearCostEstimate estimate_wear_cost(const Scenario& sc) {
  WearCostEstimate e;
  const double cpu0 = process_cpu_seconds();
  auto model = build_model(sc);
  Stepper stepper(*model);
  WearCycles cycles(*model, stepper);
  const Calibrated c = sc.wear.integrator == WearIntegrator::cycle
                           ? calibrate_carried(cycles, *model, e)
                           : calibrate_steady(cycles, *model, e);
  const SimulatedCycles range =
      expected_simulated_cycles(sc, e.implicit, e.cap, c.per_evaluation, c.first);
  e.simulated_low = range.low, e.simulated_high = range.high;
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
       " s of CPU (from " +
       (w.integrator == WearIntegrator::cycle ? "three carried cycles" : "two steady cycles") +
       " solved in " + num(e.calibration_seconds, "%.2g") + " s)\n";
  if (const std::string warn = explicit_cap_warning(w, e.cap); !warn.empty())
    o += "  " + warn + "\n";
  return o;
}

}  // namespace fretbem
