// The cost model of a run: its memory and its calibrated FFT convolutions (see
// cost_estimate.hpp).
#include "fretbem/history/cost_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "fretbem/core/format.hpp"
#include "fretbem/core/progress.hpp"
#include "fretbem/history/masing_image.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/history/resolution.hpp"
#include "fretbem/history/step_control.hpp"
#include "fretbem/history/stepper.hpp"

namespace fretbem {

namespace {

std::string num(double v, const char* fmt = "%.2g") {
  return format_printf(fmt, v);
}

// The index of the path's second turning point (the end of the first reversal), or the last
// step when there is none before it: the steps after it are settled.
std::size_t settled_from(const LoadPath& path) {
  int turnings = 0;
  for (std::size_t i = 1; i + 1 < path.steps.size(); ++i)
    if (path.steps[i].turning && ++turnings == 2) return i;
  return path.steps.size();
}

// Whether the Masing image may start steps (MasingImage::plan from the scenario alone: a path
// that can reverse, one traction component under the analogy, no wear, the predictor not
// turned off; counted wherever it could apply).
bool masing_possible(const Scenario& sc, bool two_components) {
  const bool reverses = sc.load.path == PathType::sine || sc.load.path == PathType::table;
  return reverses && sc.solver.predictor != PredictorMode::none &&
         sc.solver.coupling == Coupling::analogy && sc.wear.law == WearLaw::none && !two_components;
}

// The largest tangential target of the path: the scale of its steps' changes.
double target_scale(const LoadPath& path) {
  double scale = 0.0;
  for (const LoadStep& s : path.steps) scale = std::max(scale, s.target.norm());
  return scale;
}

// A row that repeats the row before it to kSameLoad of the path's scale (a dwell, or a table's
// first row whose target is a cosine's round-off, 6e-17 of its amplitude) costs a few products:
// it is neither calibrated on nor counted as a step (the sphere of step_control_cost.py: 3
// convolutions against 50-58 for the next rows).
bool load_unchanged(const LoadStep& a, const LoadStep& b, double scale) {
  return a.control == b.control && a.relative == b.relative &&
         a.normal.force_control == b.normal.force_control &&
         std::abs(a.normal.value - b.normal.value) <= kSameLoad * std::abs(b.normal.value) &&
         (b.target - a.target).norm() <= kSameLoad * scale;
}

// The mean over the rows whose normal load changes, weighted by their spans, of |F''| / |F| at
// the row's end (1/period^2): the second divided difference of the normal load there.
double normal_load_curvature(const LoadPath& path) {
  const std::vector<LoadStep>& s = path.steps;
  double sum = 0.0, time = 0.0;
  for (std::size_t i = 1; i + 1 < s.size(); ++i) {
    const double h0 = s[i].time - s[i - 1].time, h1 = s[i + 1].time - s[i].time;
    const double f = s[i].normal.value;
    if (!bound_moves_within(s[i - 1], s[i]) || !(h0 > 0.0 && h1 > 0.0) || f == 0.0) continue;
    const double slopes = (s[i + 1].normal.value - f) / h1 - (f - s[i - 1].normal.value) / h0;
    sum += h0 * std::abs(2.0 * slopes / (h0 + h1) / f);
    time += h0;
  }
  return time > 0.0 ? sum / time : 0.0;
}

// The sub-steps the step control of load.tolerance will give row i (1 where its normal load
// does not change): at the rate `factor` x the path's curvature (kCurvatureRateFactor), and up
// to the end of the first whole period at `calibrated` (the rate in force after the
// calibration) where it is larger.
struct SubstepForecast {
  double curvature = 0.0, calibrated = -1.0, first_period_end = 0.0, tolerance = 0.0;
  int operator()(const LoadPath& path, std::size_t i, double factor) const {
    const LoadStep &a = path.steps[i - 1], &b = path.steps[i];
    if (!bound_moves_within(a, b)) return 1;
    const double rate = factor * curvature;
    const double r = b.time <= first_period_end ? std::max(rate, calibrated) : rate;
    return substeps_for(b.time - a.time, r, tolerance);
  }
};

SubstepForecast forecast_substeps(const Model& model, const Stepper& stepper, std::size_t next) {
  SubstepForecast f;
  f.tolerance = model.scenario.load.tolerance;
  f.curvature = normal_load_curvature(model.path);
  const std::vector<LoadStep>& s = model.path.steps;
  f.first_period_end = std::ceil(s.front().time) + 1.0;
  const StepperMemory memory = stepper.memory();
  if (!memory.step_period.empty() && next < s.size())
    f.calibrated = PeriodRate::unflatten(memory.step_period)
                       .for_row(cycle_containing_end(s[next].time), s[next - 1].time);
  return f;
}

}  // namespace

MemoryEstimate estimate_memory(const Scenario& sc, bool cycle_predictor, double predictor_bytes,
                               double repeat_bytes) {
  const double cells = double(sc.grid.nx) * double(sc.grid.ny);
  const bool two = sc.solver.coupling != Coupling::analogy || sc.load.direction != 0.0 ||
                   sc.load.path == PathType::table;
  MemoryEstimate m;
  m.program = MemoryCosts::kProgramBytes;
  m.solver = cells * (two ? MemoryCosts::kSolverTwoComponents : MemoryCosts::kSolverOneComponent);
  if (sc.solver.monotone == MonotoneMethod::shortcut) m.solver += cells * MemoryCosts::kShortcut;
  // Two traction components double what the predictor remembers and starts from.
  if (cycle_predictor) m.predictor = cells * MemoryCosts::kPredictor * (two ? 2.0 : 1.0);
  // The entries of remembered sub-steps, to their bound, as the process holds them.
  if (cycle_predictor)
    m.predictor += cells * MemoryCosts::kSubstepPredictorPerByte *
                   std::max(0.0, predictor_bytes - CyclePredictor::kBytesPerCell);
  if (masing_possible(sc, two)) m.masing = cells * MemoryCosts::kMasing;
  if (sc.wear.law != WearLaw::none) m.wear = cells * (MemoryCosts::kWear + repeat_bytes);
  return m;
}

double repeat_bytes_per_cell(const Scenario& sc, const LoadPath& path) {
  const bool repeats =
      sc.wear.law != WearLaw::none && sc.wear.integrator == WearIntegrator::cycle &&
      sc.solver.coupling == Coupling::coupled && sc.solver.predictor != PredictorMode::none;
  return repeats ? 3.0 * sizeof(double) * double(path.steps.size() + 1) : 0.0;
}

ConvolutionMeter::ConvolutionMeter(const HalfSpace& half_space)
    : half_space_(half_space),
      cpu0_(process_cpu_seconds()),
      convolutions0_(half_space.convolutions()) {}

double ConvolutionMeter::seconds() const {
  return process_cpu_seconds() - cpu0_;
}

double ConvolutionMeter::convolutions() const {
  return double(half_space_.convolutions() - convolutions0_);
}

std::vector<double> step_cost_shares(const Model& model) {
  const std::size_t steps = model.path.steps.size(), settled = settled_from(model.path);
  // With the cycle predictor, a step whose load transition came before starts from that
  // step's solution (kPredictedStepShare).
  const std::vector<char> seen = model.cycle_predictor
                                     ? CyclePredictor::repeated_earlier(model.path.steps)
                                     : std::vector<char>(steps, 0);
  // A step that starts from the Masing image: exact once a branch meets the half changes of the
  // branch before it (after the second turning point: a predicted step); interpolated on the
  // first reversal, where it costs about half a calibration step (mindlin_cycle at n = 32:
  // 11.7 and 9.9 against 24 and 19 convolutions at amplitudes 0.6 and 0.3; 19.4 against 25 at
  // n = 256).
  const MasingImage::Plan masing = MasingImage::plan(model);
  const double scale = target_scale(model.path);
  std::vector<double> share(steps);
  if (model.half_space->cross_coupled()) {
    // A coupled step costs its alternations (4-10, each a normal solve and a tangential
    // re-solve), which neither a settled cycle nor a predicted start shortens: later steps
    // against the calibrated first ones, n = 32, without wear: 1.00 (combination sweep seed 45
    // case 45), 0.93 (46/11), 1.25 (42/27), 0.95 (mindlin_cycle.ini, 16 steps a cycle).
    for (std::size_t i = 0; i < steps; ++i) share[i] = row_substeps(model, i);
    return share;
  }
  for (std::size_t i = 0; i < steps; ++i) {
    const bool imaged = !masing.image.empty() && masing.image[i];
    // A row in sub-steps is that many steps. Those the cycle predictor starts (substeps_predicted)
    // cost 0.75-0.83 of a sub-step from the one before on the benches of step_control.cpp, not
    // the predicted rows' kPredictedStepShare: counted as the others, the estimate stays above.
    const int m = row_substeps(model, i);
    const bool moving = i > 0 && bound_moves_within(model.path.steps[i - 1], model.path.steps[i]);
    share[i] = i > 0 && load_unchanged(model.path.steps[i - 1], model.path.steps[i], scale)
                   ? kPredictedStepShare
               : moving                             ? m * kMovingBoundStepShare
               : seen[i] || (imaged && i > settled) ? kPredictedStepShare
               : imaged || i > settled              ? kSettledStepShare
                                                    : 1.0;
  }
  return share;
}

RunCostEstimate estimate_run_cost(const Scenario& sc) {
  RunCostEstimate e;
  const double cpu0 = process_cpu_seconds();
  auto model = build_model(sc);
  Stepper stepper(*model);
  const std::size_t steps = stepper.steps();
  // CPU time and convolutions of the solves alone (the operators' set-up excluded).
  double solve_seconds = 0.0, convolutions = 0.0, tangential = 0.0;
  auto timed = [&](std::size_t k) {
    const ConvolutionMeter meter(*model->half_space);
    const StepRecord r = stepper.advance(k);
    solve_seconds += meter.seconds();
    convolutions += r.convolutions;
    return r;
  };
  const std::vector<double> share = step_cost_shares(*model);
  const double scale = target_scale(model->path);
  const double step0 = timed(0).convolutions;
  double calibrated = 0.0;  // tangential solves: a row's sub-steps each, a row solved again twice
  double repeated = 0.0;    // convolutions of rows that repeat the row before
  std::size_t k = 1;
  for (int solved = 0; k < steps && solved < kCalibrationSteps; ++k) {
    const StepRecord r = timed(k);
    if (load_unchanged(model->path.steps[k - 1], model->path.steps[k], scale)) {
      repeated += r.convolutions;
      continue;
    }
    tangential += r.convolutions, calibrated += r.substeps, ++solved;
    if (process_cpu_seconds() - cpu0 > kCalibrationSeconds) {
      ++k;
      break;
    }
  }
  e.calibration_steps = int(k);
  const double per_step = calibrated > 0 ? tangential / calibrated : 0.0;
  const double solved = step0 + repeated + tangential;
  // Remaining steps weighted by their cost relative to a calibrated solve; under
  // load.tolerance a row's share (that of one solve) times its forecast sub-steps.
  const bool controlled = sc.load.tolerance > 0.0;
  const SubstepForecast forecast =
      controlled ? forecast_substeps(*model, stepper, k) : SubstepForecast{};
  auto remaining = [&](double factor) {
    double sum = 0.0;
    for (std::size_t i = k; i < steps; ++i)
      sum += share[i] * (controlled ? forecast(model->path, i, factor) : 1);
    return solved + per_step * sum;
  };
  e.convolutions = remaining(kCurvatureRateFactor);
  if (controlled && forecast.curvature > 0.0) {
    e.convolutions_low = remaining(kCurvatureRateRange[0]);
    e.convolutions_high = remaining(kCurvatureRateRange[1]);
  }
  e.seconds = convolutions > 0 ? e.convolutions * solve_seconds / convolutions : solve_seconds;
  e.calibration_seconds = process_cpu_seconds() - cpu0;
  return e;
}

std::string describe(const RunCostEstimate& e, std::size_t steps) {
  std::string text = "  cost: about " + num(e.convolutions, "%.3g") + " FFT convolutions, " +
                     num(e.seconds) + " s of CPU (from " + std::to_string(e.calibration_steps) +
                     " of " + std::to_string(steps) + " steps solved in " +
                     num(e.calibration_seconds) + " s; outputs not counted)\n";
  if (e.convolutions_high > 0.0 && e.convolutions > 0.0) {
    const double per = e.seconds / e.convolutions;
    text += "  load.tolerance: " + num(e.convolutions_low, "%.3g") + " to " +
            num(e.convolutions_high, "%.3g") + " FFT convolutions, " +
            num(per * e.convolutions_low) + " to " + num(per * e.convolutions_high) +
            " s of CPU (the step control's sub-steps over the measured range of its rate)\n";
  }
  return text;
}

}  // namespace fretbem
