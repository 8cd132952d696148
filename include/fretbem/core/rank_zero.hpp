// Work that one rank does for all (the output folder, the files, the terminal) with an outcome
// that every rank shares: an error on rank 0 is raised on every rank, so that no rank waits in
// a collective operation for a rank that has left (docs/mpi-grid.md, "A run on K ranks").
#pragma once

#include <functional>
#include <string>

#include "fretbem/parallel/communicator.hpp"

namespace fretbem {

/// Runs `work` on rank 0 only; then, on every rank, throws what it threw (InputError,
/// SolverError or std::runtime_error, with its message) or returns. Serial: runs `work`.
void on_rank_zero(const Communicator& comm, const std::function<void()>& work);
/// Rank 0's answer to a question only it can answer (a file, a clock), on every rank.
bool decided_on_rank_zero(const Communicator& comm, const std::function<bool()>& question);
/// Rank 0's whole number on every rank (an exit code).
long broadcast_count(const Communicator& comm, long value);
/// Rank 0's text on every rank.
std::string broadcast_text(const Communicator& comm, const std::string& text);

}  // namespace fretbem
