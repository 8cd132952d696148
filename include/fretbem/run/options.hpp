// What the command line asks of a run besides its scenario (README "Command line").
#pragma once

namespace fretbem {

struct RunOptions {
  bool quiet = false;      ///< no progress line (summaries, warnings and errors still print)
  bool overwrite = false;  ///< a fresh run may replace another run's results in its folder
  /// At most this many steps in this invocation (wear runs: simulated cycles in cycle mode,
  /// accepted integrator steps otherwise), then a checkpoint and exit; <= 0: no limit.
  long stop_after = -1;
};

}  // namespace fretbem
