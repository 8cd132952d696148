// Run outputs as observers of the stepper: the time-series CSV, the HDF5 result file and the
// progress line (DESIGN §4 "Time series", "Fields").
#pragma once

#include <chrono>
#include <memory>

#include "fretbem/io/csv_writer.hpp"
#include "fretbem/io/hdf5_writer.hpp"
#include "fretbem/stepper.hpp"

namespace fretbem {

/// DIR/timeseries.csv, one flushed row per step. Rejects NaN where the contract forbids it.
class TimeseriesCsv final : public Observer {
 public:
  explicit TimeseriesCsv(const std::filesystem::path& dir);
  void on_step(const StepRecord& rec, const InterfaceState& state, const Model& model) override;
  const std::filesystem::path& path() const { return csv_.path(); }

 private:
  io::CsvWriter csv_;
};

/// DIR/result.h5: resolved scenario, initial and final surface, time series, and the fields
/// of output.fields every output.fields_every steps, at turning points and at the last step.
class ResultFile final : public Observer {
 public:
  ResultFile(const std::filesystem::path& dir, const Model& model);
  void on_step(const StepRecord& rec, const InterfaceState& state, const Model& model) override;
  void on_finish(const InterfaceState& state, const Model& model) override;
  const std::filesystem::path& path() const { return h5_.path(); }

 private:
  io::Hdf5Writer h5_;
};

/// One progress line on stderr (step, cycle, ETA), shown once a run has taken a second.
class ProgressLine final : public Observer {
 public:
  explicit ProgressLine(std::size_t total_steps);
  void on_step(const StepRecord& rec, const InterfaceState& state, const Model& model) override;
  void on_finish(const InterfaceState& state, const Model& model) override;

 private:
  std::size_t total_;
  std::chrono::steady_clock::time_point start_, last_;
  bool shown_ = false;
};

/// The fields a run can save, by their output names, in global x-y components.
std::map<std::string, Field> output_fields(const std::vector<std::string>& names,
                                           const InterfaceState& state, const Model& model);

}  // namespace fretbem
