// How a run's end settles the results it replaces (io/replaced_results.hpp), on rank 0 only:
// a finished run removes them; a stopped one keeps them beside its checkpoint; a failed one
// puts them back and its error, rethrown with its type, says where its own files went.
#pragma once

#include <filesystem>
#include <functional>

#include "fretbem/parallel/communicator.hpp"

namespace fretbem {

/// How a run driver ended without an error: its exit code, and whether every row is done
/// (not stopped by --stop-after or a signal).
struct RunEnd {
  int code = 0;
  bool finished = false;
};

/// Runs `run` (which writes into `dir`, its lock held) and settles the results it replaces
/// as above. Returns its exit code, or rethrows its error.
int settle_replacement_at_end(const std::filesystem::path& dir, const Communicator& comm,
                              const std::function<RunEnd()>& run);

}  // namespace fretbem
