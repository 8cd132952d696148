// Tests that run on several MPI ranks (built only with FRETBEM_MPI): a test started by ctest
// runs itself again, alone, under `mpirun -n K` (this binary, --gtest_filter on its own name);
// on the ranks it does the distributed work and compares it with the serial result every rank
// also computes. The serial test passes when mpirun exits 0.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "fretbem/parallel/communicator.hpp"
#include "support/mpi_launch.hpp"
#include "support/temp_dir.hpp"

namespace mpi_test {

namespace fs = std::filesystem;

/// True on the ranks of the mpirun started by run_on_ranks.
inline bool on_ranks() {
  return fretbem::launched_on_several_ranks();
}

/// Runs the current test under mpirun -n `ranks` (fretbem_test::mpiexec_command, at most 300 s)
/// and expects exit 0, printing the ranks' output otherwise.
inline void run_on_ranks(int ranks) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string name = std::string(info->test_suite_name()) + "." + info->name();
  const fs::path log = fretbem_test::process_temp_dir() / ("mpi_" + std::string(info->name()));
  const std::string cmd = fretbem_test::mpiexec_command(ranks, 300) +
                          fs::read_symlink("/proc/self/exe").string() + " --gtest_filter=" + name +
                          " > " + log.string() + " 2>&1";
  const int s = std::system(cmd.c_str());
  std::ifstream in(log);
  std::stringstream out;
  out << in.rdbuf();
  fs::remove(log);
  EXPECT_TRUE(WIFEXITED(s) && WEXITSTATUS(s) == 0) << cmd << "\n" << out.str();
}

}  // namespace mpi_test
