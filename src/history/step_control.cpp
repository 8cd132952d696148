// Sub-stepped rows: without load.tolerance a row whose normal load changes is solved in
// load.substeps equal sub-steps along its path. Error-controlled rows: every step carries an
// embedded estimate of its error in the work (the trapezoid's error from the bound's and slip's
// differences across neighbouring steps); a row whose normal load changes is solved in equal
// sub-steps, as many as the estimate's rate asks for by its order (a period's error ~ rate x h^2
// in sub-steps of h periods; PeriodRate: until a whole period is solved a row that raises the
// rate is solved again, then a running mean). The rate, not each row's own estimate, sets the
// sub-steps: the rows' errors in the dissipation cancel over a cycle (displacement control at 32
// rows a period: rows off by up to 2 % of the cycle's energy, the cycle by 1.4e-4), and sub-steps
// placed where rows' estimates peaked missed a tolerance of 1e-4 that cheaper uniform steps met
// (docs/algorithms.md).
#include "fretbem/history/step_control.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "fretbem/core/format.hpp"
#include "fretbem/core/input_warning.hpp"
#include "fretbem/history/load_spline.hpp"
#include "fretbem/history/stepper.hpp"

namespace fretbem {

namespace {

// The trapezoid's error summed over a cycle against the error of the cycle's dissipation
// measured against its step limit (tools/bench/uniform_step_error.py, uniform steps of 32-128
// rows a period): 3.7-4.7x on the sphere, 3.5-9.7x under displacement control, 6.4-7.1x on the
// rough surface (the steps' errors partly cancel over a cycle; the bound's quadrature is not
// the only one). A third of it stays above every measured error of uniform steps (1.17x the
// least).
constexpr double kMeasuredOverestimate = 3.0;

}  // namespace

int fixed_substeps(const Model& model) {
  const LoadSpec& load = model.scenario.load;
  return load.tolerance > 0.0 ? 1 : load.substeps;  // wear and coupled: scenario/sections.cpp
}

int row_substeps(const Model& model, std::size_t k) {
  const std::vector<LoadStep>& steps = model.path.steps;
  return k > 0 && bound_moves_within(steps.at(k - 1), steps.at(k)) ? fixed_substeps(model) : 1;
}

// Measured with tools/bench/step_control_cost.py (32 rows a period in 2 and 4 sub-steps): the
// sub-steps that started from the predictor cost 0.75-0.83x those of the same rows from the
// sub-step before on the four one-component cases (sphere, rough, displacement,
// rough_displacement), and 1.12x (2 sub-steps) and 1.23x (4) under solver.coupling = cerruti
// (two components), where the sub-steps keep starting from the one before.
bool substeps_predicted(const Model& model) {
  return model.cycle_predictor && model.tangential_operator &&
         model.tangential_operator->components() == 1;
}

double predictor_bytes_per_cell(const Scenario& sc, const LoadPath& path) {
  const LoadSpec& load = sc.load;
  const int k = load.tolerance > 0.0 ? CyclePredictor::kSubstepsKept : load.substeps;
  bool moves = false;
  for (std::size_t i = 1; i < path.steps.size() && !moves; ++i)
    moves = bound_moves_within(path.steps[i - 1], path.steps[i]);
  const int factor = moves ? std::clamp(k, 1, CyclePredictor::kSubstepsKept) : 1;
  return CyclePredictor::kBytesPerCell * factor;
}

bool bound_moves_within(const LoadStep& a, const LoadStep& b) {
  return a.normal.force_control == b.normal.force_control && a.normal.value != b.normal.value &&
         a.control == b.control && a.relative == b.relative;
}

LoadStep interpolate_load(const LoadStep& a, const LoadStep& b, double theta) {
  LoadStep s = b;
  const double span = b.time - a.time;
  s.time = a.time + theta * span;
  s.cycle = cycle_of_time(s.time);
  s.turning = false;
  if (a.rate && b.rate) {  // on the table's spline
    auto on_spline = [&](double y0, double m0, double y1, double m1) {
      return hermite(y0, m0, y1, m1, span, theta);
    };
    s.normal.value = on_spline(a.normal.value, a.rate->normal, b.normal.value, b.rate->normal);
    s.target = {on_spline(a.target.x(), a.rate->target.x(), b.target.x(), b.rate->target.x()),
                on_spline(a.target.y(), a.rate->target.y(), b.target.y(), b.rate->target.y())};
    auto slope = [&](double y0, double m0, double y1, double m1) {
      return hermite_slope(y0, m0, y1, m1, span, theta);
    };
    s.rate = PathRate{slope(a.normal.value, a.rate->normal, b.normal.value, b.rate->normal),
                      {slope(a.target.x(), a.rate->target.x(), b.target.x(), b.rate->target.x()),
                       slope(a.target.y(), a.rate->target.y(), b.target.y(), b.rate->target.y())}};
    return s;
  }
  s.rate.reset();
  s.normal.value = a.normal.value + theta * (b.normal.value - a.normal.value);
  s.target = a.target + theta * (b.target - a.target);
  return s;
}

double trapezoid_work_error(const NodeStep& step0, double h0, const NodeStep& step1, double h1) {
  const double c = h1 * h1 / (6.0 * h0 * (h0 + h1));
  return c * (step0.bound_change * step1.slip - step1.bound_change * step0.slip);
}

double PeriodRate::for_row(int cycle, double t0) {
  if (cycle != cycle_ && !settled_) {  // the period booked so far is finished
    if (weight_ > 0.0) {
      rate_ = error_ / weight_;
      settled_ = end_ - start_ >= 1.0 - 1e-9;
    }
    cycle_ = cycle, start_ = end_ = t0;
    error_ = weight_ = floor_ = 0.0;
  }
  if (settled_) return rate_;
  floor_ = std::max({floor_, rate_, weight_ > 0.0 ? error_ / weight_ : 0.0});
  return floor_ > 0.0 ? floor_ : rate_;
}

double PeriodRate::with_row(double error, double span, double substep) const {
  if (settled_) return rate_;
  const double w = weight_ + span * substep * substep;
  return std::max({floor_, rate_, w > 0.0 ? (error_ + error) / w : 0.0});
}

void PeriodRate::add(double error, double span, double substep, double t1) {
  if (settled_) {  // the running mean over about a period of rows (weight span / period)
    if (span > 0.0) rate_ += std::min(span, 1.0) * (error / (span * substep * substep) - rate_);
    return;
  }
  error_ += error;
  weight_ += span * substep * substep;
  end_ = t1;
}

std::vector<double> PeriodRate::flatten() const {
  return {rate_, settled_ ? 1.0 : 0.0, cycle_, start_, end_, error_, weight_, floor_};
}

PeriodRate PeriodRate::unflatten(const std::vector<double>& v) {
  if (v.size() != kValues)
    throw std::runtime_error("step_period holds " + std::to_string(v.size()) + " values, not " +
                             std::to_string(kValues));
  PeriodRate r;
  r.rate_ = v[0], r.settled_ = v[1] != 0.0, r.cycle_ = v[2], r.start_ = v[3], r.end_ = v[4];
  r.error_ = v[5], r.weight_ = v[6], r.floor_ = v[7];
  return r;
}

int substeps_for(double span, double rate, double tolerance) {
  if (!(rate > 0.0)) return 1;
  const double wanted = span * std::sqrt(rate / tolerance);
  return int(std::clamp(std::ceil(wanted), 1.0, double(kMaxSubsteps)));
}

// Row k in sub-steps: as many as the running estimate asks for under load.tolerance, else
// fixed_substeps. The row's record is that of its last sub-step, with the work of every
// sub-step in its iteration and convolution counts and the sum of their estimates in
// step_error.
StepRecord Stepper::advance_substepped(std::size_t k) {
  const LoadStep& a = model_.path.steps.at(k - 1);
  const LoadStep& b = model_.path.steps.at(k);
  const double span = b.time - a.time;
  const bool controlled = model_.scenario.load.tolerance > 0.0;
  if (!bound_moves_within(a, b)) {  // the step does not matter: nothing to estimate
    if (!controlled) return advance(b, int(k));
    StepRecord r = estimated_substep(b, int(k), span);
    r.step_error = 0.0;
    return r;
  }
  HalfSpace& hs = *model_.half_space;
  const auto conv0 = hs.convolutions();
  row_guess_ = guess_;
  row_guess_predicted_ = guess_predicted_, row_guess_continues_ = guess_continues_;
  substep_normal_iterations_ = substep_tangential_iterations_ = substep_coupling_iterations_ = 0;
  substeps_solved_ = 0;
  StepRecord last;
  const double error = controlled ? solve_controlled(a, b, int(k), last)
                                  : solve_substeps(a, b, fixed_substeps(model_), int(k), last);
  guess_ = row_guess_;
  last.normal_iterations = substep_normal_iterations_;
  last.tangential_iterations = substep_tangential_iterations_;
  last.coupling_iterations = substep_coupling_iterations_;
  last.substeps = substeps_solved_;
  last.convolutions = int(hs.convolutions() - conv0);
  last.step_error = error;
  return last;
}

// Under load.tolerance: row a -> b in the sub-steps its period's rate asks for (PeriodRate).
// Until a whole period has set the rate, a row whose own estimate raises it to more sub-steps
// than the row was solved in is solved again in those, from the state before it: the first
// rows of a run have no rate to go by, and on the unit sphere of tests/test_step_control.cpp
// three rows solved whole at the start of the first period left it 4e-4 off its step limit
// at load.tolerance = 1e-4 with every later row of the period in 4 or 5 sub-steps.
double Stepper::solve_controlled(const LoadStep& a, const LoadStep& b, int k, StepRecord& last) {
  const double span = b.time - a.time, tolerance = model_.scenario.load.tolerance;
  const bool had_step = estimate_memory_.span > 0.0;  // else the first estimate is 0
  const int cycle = cycle_containing_end(b.time);     // the cycle cycles.csv books the row in
  int m = substeps_for(span, period_rate_.for_row(cycle, a.time), tolerance);
  std::optional<std::pair<StepperMemory, InterfaceState>> before;
  if (had_step && !period_rate_.settled()) before.emplace(memory(), state_);
  const std::size_t remembered0 = predictor_.remembered();
  double error = solve_substeps(a, b, m, k, last);
  if (before) {
    const int wanted = substeps_for(span, period_rate_.with_row(error, span, span / m), tolerance);
    if (wanted > m) {  // the sub-steps solved are not the row's: not remembered either
      predictor_.forget_newest(predictor_.remembered() - remembered0);
      restore(before->second, before->first, std::move(predictor_));
      m = wanted;
      error = solve_substeps(a, b, m, k, last);
    }
  }
  if (m == kMaxSubsteps && error > tolerance * span) say_depth_limit(k, error, span);
  period_rate_.add(had_step ? error : 0.0, had_step ? span : 0.0, span / m, b.time);
  return error;
}

// Row a -> b in m equal sub-steps; leaves `last` the last sub-step's record and returns the
// sum of their estimates (under load.tolerance; else 0) relative to the dissipation scale: the
// mean dissipation per period so far, or the row's own per period when larger. The sub-steps
// of a row the path repeats are remembered by the cycle predictor, as rows are.
double Stepper::solve_substeps(const LoadStep& a, const LoadStep& b, int m, int k,
                               StepRecord& last) {
  const double dissipation0 = dissipation_, span = (b.time - a.time) / m;
  const bool controlled = model_.scenario.load.tolerance > 0.0;
  const bool remember = m > 1 && substep_predictor_ && repeated_later_.at(std::size_t(k));
  row_whole_ = m == 1;
  substeps_solved_ += m;
  double work_error = 0.0;
  LoadStep from = a;
  for (int j = 1; j <= m; ++j) {
    const LoadStep ls = j == m ? b : interpolate_load(a, b, double(j) / m);
    start_substep(from, ls, m, k);
    substep_ = j < m;  // the row's last sub-step ends at its row: kx and the edge check there
    last = controlled ? estimated_substep(ls, k, span) : advance(ls, k);
    if (remember) predictor_.remember(from, ls, state_.traction, bound_);
    from = ls;
    work_error += last.step_error;
    substep_normal_iterations_ += last.normal_iterations;
    substep_tangential_iterations_ += last.tangential_iterations;
    substep_coupling_iterations_ += last.coupling_iterations;
  }
  substep_ = false;
  const double periods = b.time - model_.path.steps.front().time;
  const double scale =
      std::max(dissipation_ / periods, (dissipation_ - dissipation0) / (b.time - a.time));
  return scale > 0.0 ? work_error / scale : 0.0;
}

// Where sub-step from -> to of row k (in m sub-steps) starts. A row solved whole keeps the
// start the row would have without the key. A sub-step of a row whose transition came before
// starts from the same sub-step's traction one period earlier where the predictor kept it (put
// onto the moved bound, as for a split row), else from the sub-step before. The same sub-step
// only: the row's end traction one period earlier is no converged start for the row's last
// sub-step where the normal load varies (Coulomb residual 3e-5 to 1e-2 of |C g| on the sphere of
// tools/bench/step_control_cost.py, of the order of the plain start's; such last sub-steps cost
// 275-365 convolutions each there on average against 57-67 for the other sub-steps of the same
// rows; docs/algorithms.md, "Run time against error").
void Stepper::start_substep(const LoadStep& from, const LoadStep& to, int m, int k) {
  if (m == 1) {
    guess_ = row_guess_, guess_predicted_ = row_guess_predicted_;
    guess_continues_ = row_guess_continues_;
    return;
  }
  const HalfSpace& hs = *model_.half_space;
  const bool seen = substep_predictor_ && repeated_earlier_.at(std::size_t(k));
  guess_ = seen ? predictor_.find(from, to, hs.grid().nx, hs.local_rows()) : nullptr;
  guess_predicted_ = guess_ != nullptr;
  guess_continues_ = false;
}

// One step of `span` periods; its record's step_error is its estimated work error (J), and
// the step becomes the one before the next in the estimate's memory.
StepRecord Stepper::estimated_substep(const LoadStep& ls, int k, double span) {
  estimate_memory_.span_next = span;
  estimated_ = false;
  StepRecord r = advance(ls, k);
  if (!estimated_) {  // no increment ran: nothing slipped, the bound moved or not
    estimate_memory_.bound_change.setZero(bound_.rows(), bound_.cols());
    estimate_memory_.slip.setZero(bound_.rows(), bound_.cols());
    estimate_memory_.span = span;
  }
  r.step_error = estimated_ ? step_work_error_ : 0.0;
  return r;
}

// The estimate of the step accumulate_slip just booked (J): the trapezoid's error summed over
// the nodes, over the measured overestimate. Then this step becomes the one before.
void Stepper::estimate_step() {
  EstimateMemory& e = estimate_memory_;
  const Eigen::Index n = bound_.size();
  const bool moved = bound_moved_ && bound_start_.size() == n;
  const double h1 = e.span_next, h0 = e.span > 0.0 ? e.span : h1;
  if (e.slip.size() != n) e.bound_change.setZero(bound_.rows(), bound_.cols());
  if (e.slip.size() != n) e.slip.setZero(bound_.rows(), bound_.cols());
  const auto slip = std::uint8_t(NodeState::slip);
  double error = 0.0;
  for (Eigen::Index k = 0; k < n; ++k) {
    const NodeStep now{moved ? bound_(k) - bound_start_(k) : 0.0,
                       state_.state(k) == slip ? work_.slip(k) : 0.0};
    error += trapezoid_work_error({e.bound_change(k), e.slip(k)}, h0, now, h1);
    e.bound_change(k) = now.bound_change, e.slip(k) = now.slip;
  }
  e.span = h1;
  // Over every rank's nodes: the sub-steps it sets must be alike on every rank.
  error = model_.half_space->communicator().sum(error);
  const double h2 = model_.half_space->grid().cell_area();
  step_work_error_ = std::abs(error) * h2 / kMeasuredOverestimate;
  estimated_ = true;
}

// A checkpoint without the estimate's memory (written without load.tolerance, or before the
// first estimated step) starts it afresh; the period's rate is restored wherever it was written.
void Stepper::restore_estimate_memory(const StepperMemory& m) {
  estimate_memory_ = {};
  period_rate_ = {};
  if (!m.step_period.empty()) period_rate_ = PeriodRate::unflatten(m.step_period);
  const auto dg = m.fields.find("step_bound_change"), s = m.fields.find("step_slip");
  if (m.step_estimate.size() != 2 || dg == m.fields.end() || s == m.fields.end()) return;
  estimate_memory_.bound_change = dg->second, estimate_memory_.slip = s->second;
  estimate_memory_.span = m.step_estimate[0];
}

void Stepper::say_depth_limit(int k, double error, double span) {
  if (depth_limit_said_) return;
  const double tolerance = model_.scenario.load.tolerance;
  input_warning("load.tolerance = " + format_number(tolerance) + ": step " + std::to_string(k) +
                " keeps an estimated error of " + format_number(error) + " (allowed " +
                format_number(tolerance * span) + ") in " + std::to_string(kMaxSubsteps) +
                " sub-steps (the limit); step_error reports every such step");
  depth_limit_said_ = true;
}

}  // namespace fretbem
