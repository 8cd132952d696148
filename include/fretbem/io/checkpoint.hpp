// Checkpoint: the complete state of a run after a finished step, in DIR/checkpoint.h5, so that
// `fretbem run --resume DIR` continues an interrupted run exactly where it stopped. Written to
// a temporary file and renamed, so a kill mid-write leaves the previous checkpoint intact.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "fretbem/history/stepper.hpp"
#include "fretbem/wear/integrator.hpp"

namespace fretbem {

struct Checkpoint {
  std::string scenario_text;  ///< the resolved scenario of the run
  InterfaceState state;
  StepperMemory memory;
  Field surface;                       ///< current (possibly worn) indenter height (m)
  std::optional<WearCheckpoint> wear;  ///< wear runs: where the wear integration stands
};

/// Writes DIR/checkpoint.h5 atomically; `wear` for wear runs (run_wear).
void save_checkpoint(const std::filesystem::path& dir, const Model& model, const Stepper& stepper,
                     const WearCheckpoint* wear = nullptr);
/// Reads DIR/checkpoint.h5 (InputError naming the file when missing or unreadable). The
/// traction fields are shaped for `op` (same number of components as when saved).
Checkpoint load_checkpoint(const std::filesystem::path& dir);

/// Observer that checkpoints every `every` steps (0: every 10 s of run time), at turning
/// points and after the last step.
class Checkpointer final : public Observer {
 public:
  Checkpointer(std::filesystem::path dir, const Stepper& stepper, int every);
  void on_step(const StepRecord& rec, const InterfaceState& state, const Model& model) override;

 private:
  std::filesystem::path dir_;
  const Stepper& stepper_;
  int every_;
  double last_ = 0.0;
};

}  // namespace fretbem
