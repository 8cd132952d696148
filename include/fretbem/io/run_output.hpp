// Run outputs as observers of the stepper: the time-series CSV, the HDF5 result file and the
// progress line (README "Time series", "Fields").
#pragma once

#include <chrono>
#include <memory>

#include "fretbem/core/progress.hpp"
#include "fretbem/history/cycle_summary.hpp"
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

/// DIR/cycles.csv: one CycleRow per load cycle (history/cycle_summary.hpp). Ramps and
/// normal-only paths have no cycles and write no rows.
class CycleSummary final : public Observer {
 public:
  /// h: grid spacing (m).
  CycleSummary(const std::filesystem::path& dir, PathType path, double h, long resume_rows = -1);
  void on_step(const StepRecord& rec, const InterfaceState& state, const Model& model) override;
  void on_finish(const InterfaceState& state, const Model& model) override;
  static const std::vector<std::string>& columns();

 private:
  io::CsvWriter csv_;
  CycleAccumulator cycles_;
};

/// The progress report of a run (step, cycle, ETA) through ProgressReporter. The ETA counts
/// the steps' relative costs (step_cost_shares: settled and predicted steps are cheaper) from
/// the first step it sees (a resumed run's too), not the step count.
class ProgressLine final : public Observer {
 public:
  explicit ProgressLine(const Model& model, bool enabled = true);
  void on_step(const StepRecord& rec, const InterfaceState& state, const Model& model) override;
  void on_finish(const InterfaceState& state, const Model& model) override;

 private:
  std::vector<double> cost_before_;  ///< summed shares of the steps before each step
  double first_ = -1.0;              ///< cost before the first step seen (-1: none yet)
  ProgressReporter reporter_;
};

/// DIR/NAME.csv with these columns; resume_rows >= 0: keep the header and the first
/// resume_rows data rows of an existing file and append (rows an interrupted run wrote after
/// its checkpoint are dropped, not duplicated).
io::CsvWriter open_csv(const std::filesystem::path& dir, const std::string& name,
                       const std::vector<std::string>& cols, long resume_rows = -1);

/// Whether ResultFile saves output.fields at the step of `rec` (step 0, every
/// output.fields_every steps, and without wear turning points and the last step); false when
/// no field is asked. The one rule of the writer and of the gathering of a distributed state.
bool fields_saved_at(const StepRecord& rec, const Model& model);

/// The fields a run can save, by their output names, in global x-y components.
std::map<std::string, Field> output_fields(const std::vector<std::string>& names,
                                           const InterfaceState& state, const Model& model);

}  // namespace fretbem
