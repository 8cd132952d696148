#include "fretbem/io/run_output.hpp"

#include <cmath>
#include <fstream>

#include "fretbem/core/errors.hpp"
#include "fretbem/history/cost_estimate.hpp"
#include "fretbem/history/load_path.hpp"
#include "fretbem/io/xdmf_writer.hpp"

namespace fretbem {

namespace {

// Global x (c = 0) or y (c = 1) component of a field stored in the operator's basis.
Field global_component(const VecField& v, const TangentialOperator& op, int c) {
  if (op.components() == 2) return v[c];
  return v[0] * (c == 0 ? op.direction().x() : op.direction().y());
}

// 0 open, 1 stick, 2 slip (README): stuck-at-bound nodes did not slip, so they are stick.
Field state_field(const StateField& state) {
  const StateField at_bound =
      StateField::Constant(state.rows(), state.cols(), std::uint8_t(NodeState::stuck_at_bound));
  return (state == at_bound).select(double(NodeState::stick), state.cast<double>());
}

// kx = +inf is a value: a periodic grid stuck at every node is rigid (StiffnessResult::kx).
void check_finite(const StepRecord& rec, bool kx_on) {
  const auto vals = rec.values();
  const auto& cols = StepRecord::columns();
  for (std::size_t i = 0; i < vals.size(); ++i) {
    if (std::isfinite(vals[i]) || (cols[i] == "kx" && (!kx_on || vals[i] > 0))) continue;
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

bool fields_saved_at(const StepRecord& rec, const Model& m) {
  const auto& out = m.scenario.output;
  if (out.fields.empty()) return false;
  const bool every = out.fields_every > 0 && rec.step % out.fields_every == 0;
  // Step 0 (the state after the normal loading; a wear run's row 0) is where every map of
  // the history starts.
  const bool first = rec.step == 0;
  if (m.wear) return first || every;
  const bool last = std::size_t(rec.step) + 1 == m.path.steps.size();
  return first || every || rec.turning || last;
}

void ResultFile::on_step(const StepRecord& rec, const InterfaceState& s, const Model& m) {
  h5_.append_row(rec.values());
  last_step_ = rec.step, last_time_ = rec.time;
  if (fields_saved_at(rec, m)) save_fields(s, m);
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
  return CycleRow::columns();
}

CycleSummary::CycleSummary(const std::filesystem::path& dir, PathType path, double h,
                           long resume_rows)
    : csv_(open_csv(dir, "cycles", columns(), resume_rows)), cycles_(path, h) {}

void CycleSummary::on_step(const StepRecord& r, const InterfaceState&, const Model&) {
  if (const auto row = cycles_.add(r)) csv_.row(row->values());
}

void CycleSummary::on_finish(const InterfaceState&, const Model&) {
  if (const auto row = cycles_.finish()) csv_.row(row->values());
}

ProgressLine::ProgressLine(const Model& model, bool enabled) : reporter_(enabled) {
  const std::vector<double> share = step_cost_shares(model);
  cost_before_.assign(share.size() + 1, 0.0);
  for (std::size_t i = 0; i < share.size(); ++i) cost_before_[i + 1] = cost_before_[i] + share[i];
}

void ProgressLine::on_step(const StepRecord& rec, const InterfaceState&, const Model&) {
  const std::size_t total = cost_before_.size() - 1, k = std::size_t(rec.step);
  if (first_ < 0) first_ = cost_before_[k];
  const std::string where = "step " + std::to_string(k + 1) + "/" + std::to_string(total) +
                            "  cycle " + std::to_string(rec.cycle);
  const double left_at_start = cost_before_.back() - first_;
  reporter_.update(where, left_at_start > 0 ? (cost_before_[k + 1] - first_) / left_at_start : 1.0);
}

void ProgressLine::on_finish(const InterfaceState&, const Model&) {
  reporter_.finish();
}

}  // namespace fretbem
