// The progress report of long runs (steps of a load history, cycles of a wear run) on stderr.
#pragma once

#include <chrono>
#include <cstdio>
#include <ctime>
#include <string>

namespace fretbem {

/// Seconds elapsed on the steady clock since t0.
inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// CPU seconds this process has used so far (all threads). Cost estimates are in CPU time: on a
/// loaded machine, predictions from wall time were 1.2-5.5x the runs' CPU seconds
/// (docs/reliability.md, "Accuracy of check's cost estimate").
inline double process_cpu_seconds() {
  return double(std::clock()) / CLOCKS_PER_SEC;
}

/// Reports where a run stands, with elapsed time and an ETA. On a terminal one line is
/// rewritten in place ('\r'), at most every `tty_interval` seconds; anywhere else (a file, a
/// Slurm log, a pipe) a plain line is written every `log_interval` seconds, so a log holds a
/// readable line per ~10 s instead of dozens of '\r' updates run together. Nothing appears
/// before the run has taken `first_after` seconds (short runs stay silent).
class ProgressReporter {
 public:
  struct Timing {
    double first_after = 1.0;    ///< s before the first report
    double tty_interval = 0.25;  ///< s between in-place updates on a terminal
    double log_interval = 10.0;  ///< s between lines elsewhere
  };
  /// enabled = false reports nothing (--quiet). A terminal is detected with isatty(out).
  explicit ProgressReporter(bool enabled = true, std::FILE* out = stderr);
  ProgressReporter(bool enabled, std::FILE* out, Timing timing);
  ~ProgressReporter();
  ProgressReporter(const ProgressReporter&) = delete;
  ProgressReporter& operator=(const ProgressReporter&) = delete;

  /// `where` describes the position ("step 12/320  cycle 3"); `fraction` in (0, 1] gives the
  /// ETA from the elapsed time (none when <= 0).
  void update(const std::string& where, double fraction);
  /// Ends an in-place line with a newline (also done by the destructor).
  void finish();

 private:
  bool enabled_, tty_;
  std::FILE* out_;
  Timing timing_;
  std::chrono::steady_clock::time_point start_, last_;
  bool shown_ = false, line_open_ = false;
};

}  // namespace fretbem
