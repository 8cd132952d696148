// How the MPI tests start mpiexec (built only with FRETBEM_MPI).
#pragma once

#include <filesystem>
#include <string>

#include "temp_dir.hpp"

namespace fretbem_test {

/// Open MPI's session directory base for the mpiexec this test process starts: a folder of its
/// own. Under the shared default, ompi.HOST.UID in the temporary root, two mpiexec started at
/// once (ctest -j2 runs two MPI tests together) raced to create it: "mkdir ... File exists",
/// orte_init failed (TangentialSolverMpi.DisplacementControlEqualsSerial, in a clean clone's
/// .ci/run beside a combination sweep's mpirun).
inline std::string mpi_session_base() {
  const auto d = process_temp_dir() / "ompi";
  std::filesystem::create_directories(d);
  return d.string();
}

/// The command prefix for std::system that starts `ranks` ranks: the session directory, leak
/// detection off on the ranks under ASan (Open MPI 4.1.4 keeps its component and operator
/// tables to the end of the process: LeakSanitizer counted 121 kB in 3347 allocations per rank,
/// every stack inside libmpi or its unloaded plugins), `timeout` seconds when > 0 (a rank
/// blocked in a collective that another rank never entered is a failure, not a hang of the
/// suite), then mpiexec with the flags root (--allow-run-as-root) and a machine with fewer
/// free slots than ranks (--oversubscribe, docs/cluster.md) need.
inline std::string mpiexec_command(int ranks, int timeout = 0) {
  return "OMPI_MCA_orte_tmpdir_base=" + mpi_session_base() +
         " ASAN_OPTIONS=\"${ASAN_OPTIONS:-}:detect_leaks=0\" " +
         (timeout > 0 ? "timeout " + std::to_string(timeout) + " " : std::string()) +
         FRETBEM_MPIEXEC + " --allow-run-as-root --oversubscribe -n " + std::to_string(ranks) + " ";
}

}  // namespace fretbem_test
