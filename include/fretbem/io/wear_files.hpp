// The outputs of a wear run's wear events (history/observer.hpp): DIR/cycles.csv (one row per
// simulated cycle), the wear snapshots in result.h5, DIR/checkpoint.h5 after every wear step,
// and the wear progress line (README "Wear runs").
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>

#include "fretbem/core/progress.hpp"
#include "fretbem/io/csv_writer.hpp"
#include "fretbem/io/run_output.hpp"
#include "fretbem/wear/cost_estimate.hpp"
#include "fretbem/wear/integrator.hpp"

namespace fretbem {

/// A count of simulated cycles as printed: to 1e-6 cycles, whole counts as integers.
std::string simulated_count(double simulated);

/// DIR/cycles.csv, wear snapshots in result.h5, DIR/checkpoint.h5, a progress line (on
/// stderr unless quiet). `resume`: the checkpoint a resumed run continues from (its
/// cycles.csv rows and snapshot groups are kept). On a grid distributed over ranks every rank
/// holds one and calls it alike (its events are collective): rank 0 alone writes, `h5` is
/// null elsewhere, the fields are gathered to it, and an error in its writing is raised on
/// every rank.
class WearFiles final : public Observer {
 public:
  WearFiles(const Model& model, const Stepper& stepper, ResultFile* h5, bool quiet,
            const WearCheckpoint* resume);
  bool stop_requested() const override;
  void cycle(const WearCycle& c) override;
  void snapshot(double N, const Field& worn, const Field& p, bool cycle_end) override;
  void step_done(const WearCheckpoint& at) override;
  void expect(double low, double high) override { expected_ = {low, high}; }
  void warn(const std::string& line) override;
  /// Ends the progress line.
  void done() { progress_.finish(); }
  /// DIR/cycles.csv (rank 0).
  const std::filesystem::path& path() const { return csv_->path(); }
  /// N and energy_per_cycle (J) of the last accepted cycles.csv row (none yet: N < 0; rank 0).
  std::pair<double, double> last_accepted() const { return last_accepted_; }

 private:
  double done_share(double N, double simulated) const;
  void progress(double N, double simulated);

  const Communicator& comm() const { return model_.half_space->communicator(); }

  const Model& model_;
  const Stepper& stepper_;
  std::optional<io::CsvWriter> csv_;  // rank 0
  ResultFile* h5_;
  ProgressReporter progress_;
  long rows_ = 0;
  std::int64_t snapshots_ = 0;
  std::pair<double, double> last_accepted_{-1.0, 0.0};
  SimulatedCycles expected_;  // none yet (a resumed ODE run): the ETA counts on N
};

}  // namespace fretbem
