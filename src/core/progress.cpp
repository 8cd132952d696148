#include "fretbem/core/progress.hpp"

#include <unistd.h>

namespace fretbem {

ProgressReporter::ProgressReporter(bool enabled, std::FILE* out)
    : ProgressReporter(enabled, out, Timing{}) {}

ProgressReporter::ProgressReporter(bool enabled, std::FILE* out, Timing timing)
    : enabled_(enabled && out != nullptr),
      tty_(out != nullptr && isatty(fileno(out)) == 1),
      out_(out),
      timing_(timing),
      start_(std::chrono::steady_clock::now()),
      last_(start_) {}

ProgressReporter::~ProgressReporter() {
  finish();
}

void ProgressReporter::update(const std::string& where, double fraction) {
  if (!enabled_) return;
  using namespace std::chrono;
  const auto now = steady_clock::now();
  const double elapsed = duration<double>(now - start_).count();
  const double interval = tty_ ? timing_.tty_interval : timing_.log_interval;
  if (elapsed < timing_.first_after) return;
  if (shown_ && duration<double>(now - last_).count() < interval) return;
  last_ = now, shown_ = true;
  char times[96];
  if (fraction > 0 && fraction <= 1)
    std::snprintf(times, sizeof times, "  elapsed %.1f s  ETA %.1f s", elapsed,
                  elapsed * (1 - fraction) / fraction);
  else
    std::snprintf(times, sizeof times, "  elapsed %.1f s", elapsed);
  const std::string line = where + times;
  if (tty_) {
    std::fprintf(out_, "\r%s   ", line.c_str());
    line_open_ = true;
  } else {
    std::fprintf(out_, "%s\n", line.c_str());
  }
  std::fflush(out_);
}

void ProgressReporter::finish() {
  if (line_open_) std::fprintf(out_, "\n");
  line_open_ = false;
}

}  // namespace fretbem
