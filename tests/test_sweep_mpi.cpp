// fretbem sweep under mpirun (built only with FRETBEM_MPI): two ranks give the same
// sweep.csv, member by member to the last printed digit, as the serial run.
#include <gtest/gtest.h>

#include <fstream>

#include "support/mpi_launch.hpp"
#include "sweep_test_util.hpp"

using namespace sweep_test;

namespace {

std::string mpirun(int ranks) {
  return fretbem_test::mpiexec_command(ranks);
}

const std::string kSmall = " --set grid.n=32 --set load.cycles=1 --set load.steps_per_cycle=8";

}  // namespace

TEST(SweepMpi, TwoRanksGiveTheSerialSweepCsv) {
  const fs::path d = scratch("mpi");
  const fs::path serial = d / "serial", mpi = d / "mpi";
  const Result s = shell(std::string(FRETBEM_BINARY) + " sweep " + example_study() +
                             " --quiet --jobs 1 --out " + serial.string() + kSmall,
                         d);
  ASSERT_EQ(s.status, 0) << s.err;
  const Result m = shell(mpirun(2) + FRETBEM_BINARY + " sweep " + example_study() +
                             " --jobs 1 --out " + mpi.string() + kSmall,
                         d);
  ASSERT_EQ(m.status, 0) << m.err;
  EXPECT_EQ(rows_without_time(serial / "sweep.csv"), rows_without_time(mpi / "sweep.csv"));
  EXPECT_EQ(column(mpi / "sweep.csv", "status"), std::vector<std::string>(6, "ok"));
  // Every member reported once, by the rank that ran it (which rank is up to the balancing).
  int reported = 0;
  for (std::size_t p = 0; (p = m.err.find(") ok,", p)) != std::string::npos; ++p) ++reported;
  EXPECT_EQ(reported, 6) << m.err;
}

// A member that cannot converge fails on whichever rank drew it; the others complete and rank 0
// reports the failure in sweep.csv and the exit status.
TEST(SweepMpi, BadMemberIsReportedAndTheOthersComplete) {
  const fs::path d = scratch("mpi_bad");
  const fs::path study = d / "study.ini";
  std::ofstream(study) << "[study]\nscenario = " << FRETBEM_SOURCE_DIR
                       << "/scenarios/rough_fretting_cycle.ini\nout = " << (d / "out").string()
                       << "\ncombine = zip\nset = grid.n=32\nset = load.cycles=1\n"
                          "set = load.steps_per_cycle=8\n[vary]\n"
                          "solver.max_iterations = 1000, 1, 999\nsurface.seed = 1, 2, 3\n";
  const Result m = shell(mpirun(2) + FRETBEM_BINARY + " sweep " + study.string() + " --jobs 1", d);
  EXPECT_EQ(m.status, 4) << m.err;
  EXPECT_NE(m.err.find("member 1 (member_0001) failed (exit 3)"), std::string::npos) << m.err;
  EXPECT_EQ(column(d / "out" / "sweep.csv", "status"),
            (std::vector<std::string>{"ok", "failed", "ok"}));
}

// `fretbem ensemble` is not an MPI command: under mpirun every rank would run the whole
// ensemble into one folder. One line, exit 2 on every rank, nothing written.
TEST(SweepMpi, EnsembleUnderMpirunIsRefusedWithOneLine) {
  const fs::path d = scratch("mpi_ensemble");
  const Result m = shell(mpirun(2) + FRETBEM_BINARY + " ensemble " + FRETBEM_SOURCE_DIR +
                             "/scenarios/rough_monotone.ini --hurst 0.5 --seeds 2 --out " +
                             (d / "e").string() + " --set grid.n=32",
                         d);
  EXPECT_EQ(m.status, 2) << m.err;
  std::size_t lines = 0;
  for (std::size_t p = 0;
       (p = m.err.find("fretbem: error: fretbem ensemble under mpirun", p)) != std::string::npos;
       ++p)
    ++lines;
  EXPECT_EQ(lines, 1u) << m.err;
  EXPECT_FALSE(fs::exists(d / "e"));
}
