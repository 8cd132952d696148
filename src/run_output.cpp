#include "fretbem/run_output.hpp"

#include <cmath>
#include <cstdio>

#include "fretbem/errors.hpp"

namespace fretbem {

namespace {

// Global x (c = 0) or y (c = 1) component of a field stored in the operator's basis.
Field global_component(const VecField& v, const TangentialOperator& op, int c) {
  if (op.components() == 2) return v[c];
  return v[0] * (c == 0 ? op.direction().x() : op.direction().y());
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
    if (n == "state") out[n] = s.state.cast<double>();
    if (n == "slip_x") out[n] = global_component(s.slip, op, 0);
    if (n == "slip_y") out[n] = global_component(s.slip, op, 1);
    if (n == "dissipation") out[n] = s.dissipation;
    if (n == "wear") out[n] = s.wear;
  }
  return out;
}

TimeseriesCsv::TimeseriesCsv(const std::filesystem::path& dir)
    : csv_(dir, "timeseries", StepRecord::columns()) {}

void TimeseriesCsv::on_step(const StepRecord& rec, const InterfaceState&, const Model& m) {
  check_finite(rec, m.stiffness != nullptr);
  csv_.row(rec.values());
}

ResultFile::ResultFile(const std::filesystem::path& dir, const Model& m) : h5_(dir) {
  h5_.write_text("/scenario", m.scenario.resolved_text);
  h5_.write_field("/surface/initial", m.surface0);
  h5_.start_timeseries(StepRecord::columns());
}

void ResultFile::on_step(const StepRecord& rec, const InterfaceState& s, const Model& m) {
  h5_.append_row(rec.values());
  const auto& out = m.scenario.output;
  if (out.fields.empty()) return;  // fields only when asked
  const bool last = std::size_t(rec.step) + 1 == m.path.steps.size();
  const bool every = out.fields_every > 0 && rec.step % out.fields_every == 0;
  if (every || rec.turning || last)
    h5_.write_step_fields(rec.step, rec.time, output_fields(out.fields, s, m));
}

void ResultFile::on_finish(const InterfaceState&, const Model& m) {
  h5_.write_field("/surface/final", m.surface);
}

ProgressLine::ProgressLine(std::size_t total)
    : total_(total), start_(std::chrono::steady_clock::now()), last_(start_) {}

void ProgressLine::on_step(const StepRecord& rec, const InterfaceState&, const Model&) {
  using namespace std::chrono;
  const auto now = steady_clock::now();
  const double elapsed = duration<double>(now - start_).count();
  if (elapsed < 1.0 || duration<double>(now - last_).count() < 0.25) return;
  last_ = now;
  const double done = double(rec.step + 1) / double(total_);
  std::fprintf(stderr, "\rstep %d/%zu  cycle %d  elapsed %.1f s  ETA %.1f s   ", rec.step + 1,
               total_, rec.cycle, elapsed, elapsed * (1.0 - done) / done);
  shown_ = true;
}

void ProgressLine::on_finish(const InterfaceState&, const Model&) {
  if (shown_) std::fprintf(stderr, "\n");
}

}  // namespace fretbem
