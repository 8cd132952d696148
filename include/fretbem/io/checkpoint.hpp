// Checkpoint: the complete state of a run after a finished step, in DIR/checkpoint.h5, so that
// `fretbem run --resume DIR` continues an interrupted run exactly where it stopped. The file is
// built in memory, written to DIR/checkpoint.h5.tmp with every write, the fsync and the close
// checked, and only then renamed over the previous checkpoint: a full disk or a kill mid-write
// leaves the previous checkpoint intact (docs/reliability.md, "Fault tests").
#pragma once

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>

#include "fretbem/history/stepper.hpp"
#include "fretbem/io/input_digest.hpp"
#include "fretbem/wear/integrator.hpp"

namespace fretbem {

/// Layout version of checkpoint.h5 (dataset `format_version`); a reader refuses any other.
/// 2: run_id and format_version added.
constexpr int kCheckpointFormat = 2;

struct Checkpoint {
  std::string scenario_text;  ///< the resolved scenario of the run
  std::string run_id;         ///< the run whose outputs this checkpoint belongs to
  InterfaceState state;
  StepperMemory memory;
  Field surface;                       ///< current (possibly worn) indenter height (m)
  std::optional<WearCheckpoint> wear;  ///< wear runs: where the wear integration stands
  /// The cycle predictor's memory (dataset `predictor`, CyclePredictor::flatten, written when
  /// not empty; checked by validate_checkpoint); checkpoints written before it have none and
  /// resume with an empty predictor.
  std::vector<double> predictor;
  /// Fingerprints of the run's load path and initial surface (absent in checkpoints of
  /// format 2 written without them: then not checked).
  std::optional<InputDigest> inputs;
};

/// Writes DIR/checkpoint.h5 atomically (tmp file, checked writes, fsync, rename); `wear` for
/// wear runs (run_wear). Throws std::runtime_error naming the file when any write fails; the
/// previous checkpoint is then untouched.
void save_checkpoint(const std::filesystem::path& dir, const Model& model, const Stepper& stepper,
                     const WearCheckpoint* wear = nullptr);
/// Reads DIR/checkpoint.h5 (InputError naming the file and dataset when missing, unreadable
/// or internally inconsistent: any bytes give either a Checkpoint or an InputError). Checks
/// against the scenario are validate_checkpoint's (resume_check.hpp).
Checkpoint load_checkpoint(const std::filesystem::path& dir);

/// A checkpoint file starts with a 512-byte block holding the fingerprint of the HDF5 file
/// after it (core/fingerprint.hpp); load_checkpoint refuses a file whose bytes changed since
/// they were written, before HDF5 parses them. reseal_checkpoint renews the block of a
/// checkpoint edited on purpose (the fault tests do; so may a user repairing one by hand).
void reseal_checkpoint(const std::filesystem::path& file);

/// Observer that checkpoints every `every` steps (0: every 10 s of run time), at turning
/// points (at most one per second of run time) and after the last step.
class Checkpointer final : public Observer {
 public:
  Checkpointer(std::filesystem::path dir, const Stepper& stepper, int every);
  void on_step(const StepRecord& rec, const InterfaceState& state, const Model& model) override;

 private:
  std::filesystem::path dir_;
  const Stepper& stepper_;
  int every_;
  /// The last checkpoint, or the start: the 10 s count starts with the run (a step-0
  /// checkpoint is work a short run, an ensemble member, never uses).
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace fretbem
