// `fretbem run`: the whole sequence of a run, from its validated scenario (or the folder of
// an interrupted run) to its exit code (docs/architecture.md, "The run drivers"): build the
// model, lock the output folder, set aside the results it replaces, make the observers, step
// (or integrate the wear), stop and checkpoint, or resume.
#pragma once

#include <filesystem>

#include "fretbem/parallel/communicator.hpp"
#include "fretbem/run/options.hpp"
#include "fretbem/scenario/scenario.hpp"

namespace fretbem {

/// A fresh run of `sc` into sc.output.dir. Returns the exit code (0; 128 + signal when a
/// signal stopped it, checkpointed); throws on refused inputs and failed solves. A run that
/// replaces another's results (--overwrite) removes them once finished, keeps them while
/// stopped and puts them back when it fails (run/replacement_end.hpp).
/// With a distributed `comm` (mpirun -n K) the grid is split over the ranks and rank 0 writes
/// the files (docs/mpi-grid.md); every rank returns the same code or throws the same error.
int run_scenario(const Scenario& sc, const RunOptions& options,
                 const Communicator& comm = serial_communicator());

/// Continues the interrupted run in `dir` from its checkpoint (options.overwrite unused). The
/// checkpoint is validated against the scenario it carries, and the outputs against the
/// checkpoint, before anything is written. Results its run replaces are settled at its end
/// as run_scenario's; a resume refused, e.g. for a damaged checkpoint, has failed.
/// A checkpoint is the whole grid's whatever the ranks that wrote it: any K resumes it.
int resume_run(const std::filesystem::path& dir, const RunOptions& options,
               const Communicator& comm = serial_communicator());

}  // namespace fretbem
