// DIR/sweep.csv: one row per member, in member order: index, directory, the varied
// values, status (ok, failed, interrupted, running, missing), exit code, wall seconds, error, then
// the member's summary copied digit for digit from its outputs: every column of the last row of its
// cycles.csv (the steady cycle: dissipated energy, loop area, kx at the turning points, slip area
// at peak; for wear runs energy per cycle and wear volume) and final_* values of the last row of
// its timeseries.csv. Members without a column leave it empty.
#pragma once

#include <filesystem>

#include "fretbem/study/sweep_spec.hpp"

namespace fretbem {

struct SweepTally {
  int ok = 0, failed = 0;
  int running = 0;  ///< marked running: run by another process now, or killed while running
  int missing = 0;  ///< not run yet, or interrupted
};

/// Writes DIR/sweep.csv from the members' directories (atomically: a temporary file renamed).
SweepTally write_sweep_csv(const SweepSpec& spec);

}  // namespace fretbem
