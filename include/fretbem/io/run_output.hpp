// Run outputs as observers of the stepper: the time-series CSV, the HDF5 result file and the
// progress line (DESIGN §4 "Time series", "Fields").
#pragma once

#include <chrono>
#include <memory>

#include "fretbem/core/progress.hpp"
#include "fretbem/history/stepper.hpp"
#include "fretbem/io/csv_writer.hpp"
#include "fretbem/io/hdf5_writer.hpp"

namespace fretbem {

/// DIR/timeseries.csv, one flushed row per step. Rejects NaN where the contract forbids it.
class TimeseriesCsv final : public Observer {
 public:
  /// resume_rows >= 0: keep the first resume_rows data rows of an existing file and append.
  explicit TimeseriesCsv(const std::filesystem::path& dir, long resume_rows = -1);
  void on_step(const StepRecord& rec, const InterfaceState& state, const Model& model) override;
  const std::filesystem::path& path() const { return csv_.path(); }

 private:
  io::CsvWriter csv_;
};

/// DIR/result.h5: resolved scenario, initial and final surface, time series, and the fields
/// of output.fields at step 0, every output.fields_every steps, at turning points and at the
/// last step;
/// self-describing (Hdf5Writer::describe) with an XDMF sidecar (write_xdmf). In a wear run the
/// rows are the simulated cycles' steps, thousands of them: there it saves only row 0 and
/// every output.fields_every rows itself, and the wear driver adds the states it can place
/// (save_fields: the ends of the snapshots' cycles and the last state).
class ResultFile final : public Observer {
 public:
  /// resume_rows >= 0: reopen the existing file, keep that many time-series rows, append.
  ResultFile(const std::filesystem::path& dir, const Model& model, long resume_rows = -1);
  void on_step(const StepRecord& rec, const InterfaceState& state, const Model& model) override;
  void on_finish(const InterfaceState& state, const Model& model) override;
  /// Saves output.fields of `state`, the state of the last row written, as that row's step
  /// (once per step; nothing when no row was written or no field is asked).
  void save_fields(const InterfaceState& state, const Model& model);
  const std::filesystem::path& path() const { return h5_.path(); }
  /// DIR/result.xmf (saved fields over time, for ParaView) and, when the file holds wear
  /// snapshots, DIR/wear.xmf; written at the end of a run and when it stops early.
  void write_xdmf() const;
  /// The file itself, for writers of other groups (wear snapshots).
  io::Hdf5Writer& writer() { return h5_; }

 private:
  io::Hdf5Writer h5_;
  std::int64_t last_step_ = -1;  // of the last row written
  double last_time_ = 0.0;
  std::int64_t saved_step_ = -1;  // of the last fields saved
};

/// What a fresh result file starts with: its self-description, /run_id, /scenario (resolved),
/// /surface/initial and an empty /timeseries of StepRecord's columns.
void write_result_header(io::Hdf5Writer& h5, const Model& model);

/// DIR/cycles.csv: per load cycle (period 1 in time) the energy dissipated (nodal sums), the
/// loop area of the F-U path (trapezoid rule, x and y), force and shift amplitudes, k_x and the
/// slip area at the cycle's turning points, and the resolution there (slip-ring width in cells,
/// contact nodes, equivalent contact radius sqrt(A/pi)/h: a/h for a sphere). A step's increment
/// belongs to the cycle that contains its time interval (t_{k-1}, t_k]. Ramps and normal-only
/// paths have no cycles and write no rows.
class CycleSummary final : public Observer {
 public:
  explicit CycleSummary(const std::filesystem::path& dir, long resume_rows = -1);
  void on_step(const StepRecord& rec, const InterfaceState& state, const Model& model) override;
  void on_finish(const InterfaceState& state, const Model& model) override;
  static const std::vector<std::string>& columns();

 private:
  void flush_cycle();
  io::CsvWriter csv_;
  bool have_prev_ = false;
  StepRecord prev_;
  bool in_cycle_ = false;  // cycle_ holds a cycle (table times may be negative: no sentinel)
  int cycle_ = 0;
  double diss0_ = 0, loop_ = 0, fmin_ = 0, fmax_ = 0, umin_ = 0, umax_ = 0;
  // kx at the extreme-F_x turning points; kx at the extreme-F_x steps for a cycle without one.
  double k_at_max_ = 0, k_at_min_ = 0, slip_at_peak_ = 0, peak_ = -1;
  double k_any_max_ = 0, k_any_min_ = 0;
  bool turn_max_ = false, turn_min_ = false;
  double ring_ = -1, ring_radius_ = 0;
  long ring_nodes_ = 0;
  bool ring_at_peak_ = false;
  int steps_ = 0;
};

/// The progress report of a run (step, cycle, ETA) through ProgressReporter.
class ProgressLine final : public Observer {
 public:
  explicit ProgressLine(std::size_t total_steps, bool enabled = true);
  void on_step(const StepRecord& rec, const InterfaceState& state, const Model& model) override;
  void on_finish(const InterfaceState& state, const Model& model) override;

 private:
  std::size_t total_;
  ProgressReporter reporter_;
};

/// A run stopped early with its checkpoint written (`where`: "K of N steps", "N = K of M"):
/// by --stop-after, one line on stdout and 0; by SIGTERM/SIGINT (core/stop_signal.hpp), one
/// line on stderr and 128 + the signal, as a shell reports a killed job. Both say how to
/// continue.
int report_stop(const std::string& where, const std::filesystem::path& dir);

/// DIR/NAME.csv with these columns; resume_rows >= 0: keep the header and the first
/// resume_rows data rows of an existing file and append (rows an interrupted run wrote after
/// its checkpoint are dropped, not duplicated).
io::CsvWriter open_csv(const std::filesystem::path& dir, const std::string& name,
                       const std::vector<std::string>& cols, long resume_rows = -1);

/// The fields a run can save, by their output names, in global x-y components.
std::map<std::string, Field> output_fields(const std::vector<std::string>& names,
                                           const InterfaceState& state, const Model& model);

}  // namespace fretbem
