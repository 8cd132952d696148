// `fretbem run` under mpirun -n 2 (built only with FRETBEM_MPI): a run is not distributed yet,
// so it is refused with one line naming mpirun, before any output is written; and
// `mpirun -n 1` is a serial run.
#include <gtest/gtest.h>

#include "sweep_test_util.hpp"

using namespace sweep_test;

namespace {

std::string mpirun(int ranks) {
  return "ASAN_OPTIONS=\"${ASAN_OPTIONS:-}:detect_leaks=0\" timeout 300 " +
         std::string(FRETBEM_MPIEXEC) + " --allow-run-as-root --oversubscribe -n " +
         std::to_string(ranks) + " ";
}

std::string mindlin() {
  return (fs::path(FRETBEM_SOURCE_DIR) / "scenarios" / "mindlin_cycle.ini").string();
}

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (std::size_t p = 0; (p = text.find(what, p)) != std::string::npos; ++p) ++n;
  return n;
}

}  // namespace

TEST(RunMpi, TwoRanksAreRefusedWithOneLine) {
  const fs::path d = scratch("run_mpi");
  for (const std::string& extra : {std::string(), " --resume " + (d / "out").string()}) {
    const std::string cmd = mpirun(2) + FRETBEM_BINARY + " run " +
                            (extra.empty() ? mindlin() + " --out " + (d / "out").string() : extra) +
                            " --quiet --set grid.n=16";
    const Result r = shell(cmd, d);
    EXPECT_NE(r.status, 0) << r.err;
    EXPECT_EQ(count(r.err, "fretbem: error: fretbem run under mpirun -n K > 1"), 1) << r.err;
    EXPECT_FALSE(fs::exists(d / "out")) << "nothing written";
  }
}

TEST(RunMpi, OneRankIsASerialRun) {
  const fs::path d = scratch("run_mpi_one");
  const std::string args = " run " + mindlin() +
                           " --quiet --set grid.n=16 --set load.cycles=1 --set "
                           "load.steps_per_cycle=8 --out ";
  const Result s = shell(std::string(FRETBEM_BINARY) + args + (d / "serial").string(), d);
  ASSERT_EQ(s.status, 0) << s.err;
  const Result m = shell(mpirun(1) + FRETBEM_BINARY + args + (d / "mpi").string(), d);
  ASSERT_EQ(m.status, 0) << m.err;
  EXPECT_EQ(slurp(d / "serial" / "timeseries.csv"), slurp(d / "mpi" / "timeseries.csv"));
}
