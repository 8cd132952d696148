// A run without wear: the Stepper over the whole load path and the observers that write its
// outputs (timeseries.csv, result.h5, cycles.csv, checkpoint.h5, the resolution report, the
// progress line), then the summary on stdout.
#pragma once

#include "fretbem/history/stepper.hpp"
#include "fretbem/run/options.hpp"

namespace fretbem {

/// Runs the remaining steps of `stepper` (a fresh one, or one restored from a checkpoint after
/// `resume_rows` rows; -1: a fresh run). Returns the exit code (report_stop's when stopped).
int run_steps(Model& model, Stepper& stepper, long resume_rows, const RunOptions& options);

}  // namespace fretbem
