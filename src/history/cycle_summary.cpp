#include "fretbem/history/cycle_summary.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "fretbem/history/resolution.hpp"

namespace fretbem {

const std::vector<std::string>& CycleRow::columns() {
  static const std::vector<std::string> c{
      "cycle",         "steps",     "dissipated_energy", "loop_area",         "Fx_amplitude",
      "Ux_amplitude",  "kx_at_max", "kx_at_min",         "slip_area_at_peak", "slip_ring_cells",
      "contact_nodes", "a_over_h",  "step_error"};
  return c;
}

std::vector<double> CycleRow::values() const {
  return {
      double(cycle),         double(steps), dissipated_energy, loop_area,         Fx_amplitude,
      Ux_amplitude,          kx_at_max,     kx_at_min,         slip_area_at_peak, slip_ring_cells,
      double(contact_nodes), a_over_h,      step_error};
}

CycleAccumulator::CycleAccumulator(PathType path, double h)
    : cyclic_(path != PathType::none && path != PathType::ramp), h_(h) {}

void CycleAccumulator::start_cycle(int cycle) {
  in_cycle_ = true, cycle_ = cycle, diss0_ = prev_.dissipation, loop_ = 0, steps_ = 0;
  step_error_ = 0;
  peak_ = -1, fmin_ = fmax_ = prev_.Fx, umin_ = umax_ = prev_.Ux;
  ring_ = -1, ring_at_peak_ = false, turn_max_ = turn_min_ = false;
}

// Resolution at the cycle's load peaks (the narrowest ring), else at its last step.
void CycleAccumulator::track_resolution(const StepRecord& r) {
  const bool peak = load_peak(r, prev_);
  if ((peak && (ring_ < 0 || r.slip_ring_cells < ring_ || !ring_at_peak_)) || !ring_at_peak_) {
    ring_ = r.slip_ring_cells, ring_nodes_ = r.contact_nodes;
    ring_radius_ = std::sqrt(r.contact_area / M_PI) / h_;
    ring_at_peak_ = ring_at_peak_ || peak;
  }
}

// Which step is the cycle's largest (smallest) F_x and which turning point its peak |F_x| is
// decided with kSameLoad: points of one load (a table's +Q rows) differ by round-off that
// depends on the ranks: a plain comparison picks another row on two ranks than serially, and
// a run resumed on another layout mixes rows of both. Of equal loads the last step gives k_x
// and the first turning point the slip area (the choices of >= and > in exact arithmetic).
void CycleAccumulator::track_extremes(const StepRecord& r) {
  if (steps_ == 0 || !load_exceeds(fmax_, r.Fx)) k_any_max_ = r.kx;
  if (steps_ == 0 || !load_exceeds(-fmin_, -r.Fx)) k_any_min_ = r.kx;
  fmin_ = std::min(fmin_, r.Fx), fmax_ = std::max(fmax_, r.Fx);
  umin_ = std::min(umin_, r.Ux), umax_ = std::max(umax_, r.Ux);
  if (r.turning && !load_exceeds(fmax_, r.Fx)) k_at_max_ = r.kx, turn_max_ = true;
  if (r.turning && !load_exceeds(-fmin_, -r.Fx)) k_at_min_ = r.kx, turn_min_ = true;
  if (r.turning && load_exceeds(std::abs(r.Fx), peak_))
    peak_ = std::abs(r.Fx), slip_at_peak_ = r.slip_area;
}

std::optional<CycleRow> CycleAccumulator::add(const StepRecord& r) {
  if (!cyclic_) return std::nullopt;
  if (!have_prev_ || r.step == 0) {
    prev_ = r, have_prev_ = true;
    return std::nullopt;
  }
  std::optional<CycleRow> closed;
  const int cycle = cycle_containing_end(r.time);
  if (!in_cycle_ || cycle != cycle_) {
    closed = finish();
    start_cycle(cycle);
  }
  track_resolution(r);
  // Work of the tangential force over the step (trapezoid): the loop area over a cycle.
  loop_ +=
      0.5 * (r.Fx + prev_.Fx) * (r.Ux - prev_.Ux) + 0.5 * (r.Fy + prev_.Fy) * (r.Uy - prev_.Uy);
  track_extremes(r);
  step_error_ += r.step_error;
  ++steps_;
  prev_ = r;
  return closed;
}

CycleRow CycleAccumulator::row() const {
  CycleRow c;
  c.cycle = cycle_, c.steps = steps_, c.dissipated_energy = prev_.dissipation - diss0_;
  c.loop_area = loop_, c.Fx_amplitude = 0.5 * (fmax_ - fmin_),
  c.Ux_amplitude = 0.5 * (umax_ - umin_);
  c.kx_at_max = turn_max_ ? k_at_max_ : k_any_max_;
  c.kx_at_min = turn_min_ ? k_at_min_ : k_any_min_;
  c.slip_area_at_peak = slip_at_peak_;
  c.slip_ring_cells = ring_, c.contact_nodes = ring_nodes_, c.a_over_h = ring_radius_;
  c.step_error = step_error_;
  return c;
}

std::optional<CycleRow> CycleAccumulator::finish() {
  if (!in_cycle_ || steps_ == 0) return std::nullopt;
  in_cycle_ = false;
  return row();
}

CycleMeter::CycleMeter(double dissipation0, Field slip_path0, const Communicator& comm)
    : dissipation0_(dissipation0), slip_path0_(std::move(slip_path0)), comm_(&comm) {
  m_.stick_area = INFINITY;
}

// Over the ranks; -inf for an empty slab.
double CycleMeter::largest(const Field& x) const {
  return comm_->max(x.size() ? x.maxCoeff() : -HUGE_VAL);
}

// The row's indentation, contact radius and peak pressure are those at the period's end
// (phase 0), which a carried cycle ends on and a steady loop passes through; under a varying
// normal load its last step (the first turning point) is at another load, so an ODE row and
// a cycle row of the same surface disagreed (by 1.6x the max worn depth in delta,
// tools/bench/wear_sweep.py, table with Fz 10/12/8/12 N). A merged-away period end lies
// inside a monotone segment at constant normal load: then the last step stands for it.
void CycleMeter::add(const StepRecord& r, const InterfaceState& s, double phase) {
  m_.stick_area = std::min(m_.stick_area, r.stick_area);
  if (at_phase0_) return;
  contact_ = r.contact_area;
  m_.delta = r.delta;
  m_.peak_pressure = largest(s.pressure);
  at_phase0_ = std::abs(phase - std::round(phase)) <= 1e-9;
}

CycleMeasures CycleMeter::finish(double dissipation, const InterfaceState& s) const {
  CycleMeasures m = m_;
  m.energy = dissipation - dissipation0_;
  m.contact_radius = std::sqrt(contact_ / std::numbers::pi);
  // Stability of explicit steps involves only nodes in contact (a separated node neither
  // wears nor passes load on), so the largest slip is taken over them.
  m.max_slip = largest((s.pressure > 0.0).cast<double>() * (s.slip_path - slip_path0_));
  return m;
}

}  // namespace fretbem
