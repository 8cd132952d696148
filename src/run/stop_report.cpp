#include "fretbem/run/stop_report.hpp"

#include <csignal>
#include <cstdio>

#include "fretbem/core/stop_signal.hpp"

namespace fretbem {

int report_stop(const std::string& where, const std::filesystem::path& dir) {
  return report_stop(where, dir, stop_signal());
}

int report_stop(const std::string& where, const std::filesystem::path& dir, int sig) {
  if (sig == 0) {
    std::printf("fretbem: stopped after %s; continue with: fretbem run --resume %s\n",
                where.c_str(), dir.string().c_str());
    return 0;
  }
  std::fprintf(stderr,
               "fretbem: stopped by %s after %s, checkpoint written; continue with: fretbem run "
               "--resume %s\n",
               sig == SIGINT ? "SIGINT" : "SIGTERM", where.c_str(), dir.string().c_str());
  return 128 + sig;
}

}  // namespace fretbem
