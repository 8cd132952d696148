// The message and exit code of a run stopped early (README "Stopping and resuming").
#pragma once

#include <filesystem>
#include <string>

namespace fretbem {

/// A run stopped early with its checkpoint written (`where`: "K of N steps", "N = K of M"):
/// by --stop-after, one line on stdout and 0; by SIGTERM/SIGINT (core/stop_signal.hpp), one
/// line on stderr and 128 + the signal, as a shell reports a killed job. Both say how to
/// continue.
int report_stop(const std::string& where, const std::filesystem::path& dir);
/// The same for a stop by signal `sig` (0: by --stop-after): on a grid distributed over ranks,
/// the signal one of the ranks received.
int report_stop(const std::string& where, const std::filesystem::path& dir, int sig);

}  // namespace fretbem
