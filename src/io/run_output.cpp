#include "fretbem/io/run_output.hpp"

#include <cmath>
#include <csignal>
#include <cstdio>
#include <fstream>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/stop_signal.hpp"
#include "fretbem/history/load_path.hpp"
#include "fretbem/history/resolution.hpp"
#include "fretbem/io/xdmf_writer.hpp"

namespace fretbem {

namespace {

// Global x (c = 0) or y (c = 1) component of a field stored in the operator's basis.
Field global_component(const VecField& v, const TangentialOperator& op, int c) {
  if (op.components() == 2) return v[c];
  return v[0] * (c == 0 ? op.direction().x() : op.direction().y());
}

// 0 open, 1 stick, 2 slip (DESIGN §4): stuck-at-bound nodes did not slip, so they are stick.
Field state_field(const StateField& state) {
  const StateField at_bound =
      StateField::Constant(state.rows(), state.cols(), std::uint8_t(NodeState::stuck_at_bound));
  return (state == at_bound).select(double(NodeState::stick), state.cast<double>());
}

void check_finite(const StepRecord& rec, bool kx_on) {
  const auto vals = rec.values();
  const auto& cols = StepRecord::columns();
  for (std::size_t i = 0; i < vals.size(); ++i) {
    if (std::isfinite(vals[i]) || (cols[i] == "kx" && !kx_on)) continue;
    throw SolverError("step " + std::to_string(rec.step) + ": " + cols[i] +
                      " is not finite; the run stops here (rows so far are written)");
  }
}

}  // namespace

std::map<std::string, Field> output_fields(const std::vector<std::string>& names,
                                           const InterfaceState& s, const Model& m) {
  const TangentialOperator& op = *m.tangential_operator;
  std::map<std::string, Field> out;
  for (const auto& n : names) {
    if (n == "pressure") out[n] = s.pressure;
    if (n == "traction_x") out[n] = global_component(s.traction, op, 0);
    if (n == "traction_y") out[n] = global_component(s.traction, op, 1);
    if (n == "state") out[n] = state_field(s.state);
    if (n == "slip_x") out[n] = global_component(s.slip, op, 0);
    if (n == "slip_y") out[n] = global_component(s.slip, op, 1);
    if (n == "dissipation") out[n] = s.dissipation;
    if (n == "wear") out[n] = s.wear;
  }
  return out;
}

namespace {

// Keeps the header and the first `rows` data rows of DIR/NAME.csv (resume).
void truncate_csv(const std::filesystem::path& dir, const std::string& name, long rows) {
  if (rows < 0) return;
  const auto path = dir / (name + ".csv");
  std::ifstream in(path);
  if (!in) return;
  std::string line, kept;
  for (long k = 0; k <= rows && std::getline(in, line); ++k) kept += line + "\n";
  in.close();
  std::ofstream(path, std::ios::trunc) << kept;
}

}  // namespace

io::CsvWriter open_csv(const std::filesystem::path& dir, const std::string& name,
                       const std::vector<std::string>& cols, long resume_rows) {
  truncate_csv(dir, name, resume_rows);
  return io::CsvWriter(dir, name, cols, resume_rows >= 0);
}

TimeseriesCsv::TimeseriesCsv(const std::filesystem::path& dir, long resume_rows)
    : csv_(open_csv(dir, "timeseries", StepRecord::columns(), resume_rows)) {}

void TimeseriesCsv::on_step(const StepRecord& rec, const InterfaceState&, const Model& m) {
  check_finite(rec, stiffness_wanted(m, rec.step, rec.turning));
  csv_.row(rec.values());
}

int report_stop(const std::string& where, const std::filesystem::path& dir) {
  const int sig = stop_signal();
  if (sig == 0) {
    std::printf("fretbem: stopped after %s; continue with: fretbem run --resume %s\n",
                where.c_str(), dir.string().c_str());
    return 0;
  }
  std::fprintf(stderr,
               "fretbem: stopped by %s after %s, checkpoint written; continue with: fretbem run "
               "--resume %s\n",
               sig == SIGINT ? "SIGINT" : "SIGTERM", where.c_str(), dir.string().c_str());
  return 128 + sig;
}

void write_result_header(io::Hdf5Writer& h5, const Model& m) {
  h5.describe(m.scenario.grid, m.scenario.output.dir);
  h5.write_text("/run_id", m.run_id);
  h5.write_text("/scenario", m.scenario.resolved_text);
  h5.write_field("/surface/initial", m.surface0);
  h5.start_timeseries(StepRecord::columns());
}

ResultFile::ResultFile(const std::filesystem::path& dir, const Model& m, long resume_rows)
    : h5_(resume_rows >= 0 ? io::Hdf5Writer::open_existing(dir) : io::Hdf5Writer(dir)) {
  if (resume_rows < 0) {
    write_result_header(h5_, m);
    return;
  }
  h5_.describe(m.scenario.grid, m.scenario.output.dir);
  h5_.truncate_timeseries(std::size_t(resume_rows));
}

void ResultFile::on_step(const StepRecord& rec, const InterfaceState& s, const Model& m) {
  h5_.append_row(rec.values());
  last_step_ = rec.step, last_time_ = rec.time;
  const auto& out = m.scenario.output;
  const bool every = out.fields_every > 0 && rec.step % out.fields_every == 0;
  // Step 0 (the state after the normal loading; a wear run's row 0) is where every map of
  // the history starts.
  const bool first = rec.step == 0;
  if (m.wear) {
    if (first || every) save_fields(s, m);
    return;
  }
  const bool last = std::size_t(rec.step) + 1 == m.path.steps.size();
  if (first || every || rec.turning || last) save_fields(s, m);
}

void ResultFile::save_fields(const InterfaceState& s, const Model& m) {
  const auto& names = m.scenario.output.fields;
  if (names.empty() || last_step_ < 0 || last_step_ == saved_step_) return;
  h5_.write_step_fields(last_step_, last_time_, output_fields(names, s, m));
  saved_step_ = last_step_;
}

void ResultFile::on_finish(const InterfaceState&, const Model& m) {
  // Without wear the surface ends as it began: one dataset under both names.
  if (m.surface.rows() == m.surface0.rows() && m.surface.cols() == m.surface0.cols() &&
      (m.surface == m.surface0).all())
    h5_.link("/surface/initial", "/surface/final");
  else
    h5_.write_field("/surface/final", m.surface);
  write_xdmf();
}

void ResultFile::write_xdmf() const {
  const auto dir = h5_.path().parent_path();
  io::write_xdmf(h5_.path(), dir / "result.xmf", "/fields");
  io::write_xdmf(h5_.path(), dir / "wear.xmf", "/wear");
}

const std::vector<std::string>& CycleSummary::columns() {
  static const std::vector<std::string> c{"cycle",           "steps",         "dissipated_energy",
                                          "loop_area",       "Fx_amplitude",  "Ux_amplitude",
                                          "kx_at_max",       "kx_at_min",     "slip_area_at_peak",
                                          "slip_ring_cells", "contact_nodes", "a_over_h"};
  return c;
}

CycleSummary::CycleSummary(const std::filesystem::path& dir, long resume_rows)
    : csv_(open_csv(dir, "cycles", columns(), resume_rows)) {}

void CycleSummary::on_step(const StepRecord& r, const InterfaceState&, const Model& m) {
  // Ramps and normal-only paths have no cycles: the file keeps its header only (issue 18).
  const PathType path = m.scenario.load.path;
  if (path == PathType::none || path == PathType::ramp) return;
  if (!have_prev_ || r.step == 0) {
    prev_ = r, have_prev_ = true;
    return;
  }
  const int cycle = cycle_containing_end(r.time);
  if (!in_cycle_ || cycle != cycle_) {
    flush_cycle();
    in_cycle_ = true, cycle_ = cycle, diss0_ = prev_.dissipation, loop_ = 0, steps_ = 0;
    peak_ = -1, fmin_ = fmax_ = prev_.Fx, umin_ = umax_ = prev_.Ux;
    ring_ = -1, ring_at_peak_ = false, turn_max_ = turn_min_ = false;
  }
  // Resolution at the cycle's load peaks (the narrowest ring), else at its last step.
  if (load_peak(r, prev_) && (ring_ < 0 || r.slip_ring_cells < ring_ || !ring_at_peak_))
    ring_ = r.slip_ring_cells, ring_nodes_ = r.contact_nodes, ring_at_peak_ = true,
    ring_radius_ = std::sqrt(r.contact_area / M_PI) / m.scenario.grid.h;
  if (!ring_at_peak_)
    ring_ = r.slip_ring_cells, ring_nodes_ = r.contact_nodes,
    ring_radius_ = std::sqrt(r.contact_area / M_PI) / m.scenario.grid.h;
  // Work of the tangential force over the step (trapezoid): the loop area over a cycle.
  loop_ +=
      0.5 * (r.Fx + prev_.Fx) * (r.Ux - prev_.Ux) + 0.5 * (r.Fy + prev_.Fy) * (r.Uy - prev_.Uy);
  if (steps_ == 0 || r.Fx >= fmax_) k_any_max_ = r.kx;
  if (steps_ == 0 || r.Fx <= fmin_) k_any_min_ = r.kx;
  fmin_ = std::min(fmin_, r.Fx), fmax_ = std::max(fmax_, r.Fx);
  umin_ = std::min(umin_, r.Ux), umax_ = std::max(umax_, r.Ux);
  if (r.turning && r.Fx >= fmax_) k_at_max_ = r.kx, turn_max_ = true;
  if (r.turning && r.Fx <= fmin_) k_at_min_ = r.kx, turn_min_ = true;
  if (r.turning && std::abs(r.Fx) > peak_) peak_ = std::abs(r.Fx), slip_at_peak_ = r.slip_area;
  ++steps_;
  prev_ = r;
}

void CycleSummary::flush_cycle() {
  if (!in_cycle_ || steps_ == 0) return;
  // A cycle without a turning point at its extreme F_x (a table that ends or starts mid-way)
  // reports kx at its extreme-F_x step (issue 14 item 13: it reported 0 or a stale value).
  const double k_max = turn_max_ ? k_at_max_ : k_any_max_;
  const double k_min = turn_min_ ? k_at_min_ : k_any_min_;
  csv_.row({double(cycle_), double(steps_), prev_.dissipation - diss0_, loop_,
            0.5 * (fmax_ - fmin_), 0.5 * (umax_ - umin_), k_max, k_min, slip_at_peak_, ring_,
            double(ring_nodes_), ring_radius_});
}

void CycleSummary::on_finish(const InterfaceState&, const Model&) {
  flush_cycle();
  in_cycle_ = false;
}

ProgressLine::ProgressLine(std::size_t total, bool enabled) : total_(total), reporter_(enabled) {}

void ProgressLine::on_step(const StepRecord& rec, const InterfaceState&, const Model&) {
  const std::string where = "step " + std::to_string(rec.step + 1) + "/" + std::to_string(total_) +
                            "  cycle " + std::to_string(rec.cycle);
  reporter_.update(where, double(rec.step + 1) / double(total_));
}

void ProgressLine::on_finish(const InterfaceState&, const Model&) {
  reporter_.finish();
}

}  // namespace fretbem
