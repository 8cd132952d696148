// Hostile-user faults of studies and ensembles (issue 14, session 6; tools/bench/hostile_hunt.py
// found each of these): summaries on a full disk, two studies into one folder, a member still
// run by another process, study files and options a careless user types, ensembles of what
// cannot be aggregated. Members are n = 32, one cycle of 8 steps (well under a second each).
#include <gtest/gtest.h>
#include <sys/mount.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include "fretbem/core/file_lock.hpp"
#include "fretbem/core/text_file.hpp"
#include "sweep_test_util.hpp"

using namespace fretbem;
using namespace sweep_test;

namespace {

const std::string kBin = FRETBEM_BINARY;
const std::string kRough = std::string(FRETBEM_SOURCE_DIR) + "/scenarios/rough_monotone.ini";
const std::string kMindlin = std::string(FRETBEM_SOURCE_DIR) + "/scenarios/mindlin_cycle.ini";

// A four-member study of the Mindlin sphere, small.
fs::path small_study(const fs::path& dir, const std::string& head = "") {
  const fs::path f = dir / "study.ini";
  std::ofstream(f) << head << "[study]\nscenario = " << kMindlin
                   << "\nset = grid.n=32\nset = load.cycles=1\nset = load.steps_per_cycle=8\n"
                      "[vary]\nload.amplitude = 0.3, 0.5, 0.7, 0.8\n";
  return f;
}

int lines(const std::string& s) {
  return int(std::count(s.begin(), s.end(), '\n'));
}

int count_of(const std::string& s, const std::string& what) {
  int n = 0;
  for (std::size_t p = 0; (p = s.find(what, p)) != std::string::npos; ++p) ++n;
  return n;
}

}  // namespace

// Each ran to exit 0 before: identical members of a sphere (a zero-width interval), k_x columns
// all nan, an aggregate of empty bins; --seeds 2147483647 looped forever.
TEST(StudyFaults, EnsembleRefusesWhatItCannotAggregate) {
  const fs::path d = scratch("ensemble_refusals");
  const std::string base = kBin + " ensemble " + kRough + " --hurst 0.5 --seeds 2 --quiet --out " +
                           (d / "e").string() + " --set grid.n=16 --set load.steps=3";
  std::ofstream(d / "file") << "x";
  const struct {
    std::string args, says;
  } cases[] = {
      {" --set surface.type=sphere --set surface.radius=0.01", "surface.type must be rough"},
      {" --set solver.stiffness=none", "solver.stiffness must be every"},
      {" --set solver.stiffness=turning", "solver.stiffness must be every"},
      {" --set load.path=none", "load.path = none"},
      {" --seeds 2147483647", "--seeds"},
  };
  for (const auto& c : cases) {
    const Result r = shell(base + c.args, d);
    EXPECT_EQ(r.status, 2) << c.args << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << r.err;
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_FALSE(fs::exists(d / "e" / "H0.5")) << c.args;
  }
  // --out naming a file: the run's message and exit code (it was exit 1, "cannot create
  // directories").
  const Result r = shell(kBin + " ensemble " + kRough + " --hurst 0.5 --out " +
                             (d / "file").string() + " --set grid.n=16",
                         d);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("cannot create the output folder"), std::string::npos) << r.err;
}

// Two studies of the same file into one folder at once (a Slurm requeue beside the old job, a
// second terminal): every member runs exactly once, the other study leaves it alone, and the
// results equal one study's. Before, the second emptied a member's folder under the running
// member, and members failed on each other's locks ("failed (exit 2)" with another member's log
// line as the error).
TEST(StudyFaults, TwoSweepsIntoOneFolderShareTheMembers) {
  const fs::path d = scratch("two_sweeps");
  const fs::path study = small_study(d), out = d / "out";
  const std::string cmd = kBin + " sweep " + study.string() + " --jobs 1 --out " + out.string();
  const Result r = shell("(" + cmd + " 2> " + (d / "a.err").string() + " & " + cmd + "; wait)", d);
  const std::string both = r.err + slurp(d / "a.err");
  EXPECT_EQ(count_of(both, ") ok,"), 4) << both;  // every member ran once
  EXPECT_EQ(count_of(both, "failed ("), 0) << both;
  EXPECT_EQ(
      shell(kBin + " sweep " + study.string() + " --aggregate --out " + out.string(), d).status, 0);
  EXPECT_EQ(column(out / "sweep.csv", "status"), std::vector<std::string>(4, "ok"));
}

// A member another process holds is left to it: the study's member lock (another study), or the
// member's own run lock (a `fretbem run` orphaned by a study killed with SIGKILL, which a rerun
// used to delete under it). The rerun after the locks are gone runs just those members.
TEST(StudyFaults, SweepLeavesMembersOthersRun) {
  const fs::path d = scratch("held_members");
  const fs::path study = small_study(d), out = d / "out";
  fs::create_directories(out / "member_0001");
  {
    auto study_lock = FileLock::try_lock(out / ".member_0000.lock");
    auto run_lock = FileLock::try_lock(out / "member_0001" / ".fretbem.lock");
    ASSERT_TRUE(study_lock && run_lock);
    std::ofstream(out / "member_0001" / "timeseries.csv") << "step\n0\n";  // the orphan's
    const Result r =
        shell(kBin + " sweep " + study.string() + " --jobs 1 --out " + out.string(), d);
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("member 0 (member_0000) is being run by another fretbem process"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("member 1 (member_0001): a fretbem run is still writing into it"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(slurp(out / "member_0001" / "timeseries.csv"), "step\n0\n");  // left alone
    EXPECT_EQ(column(out / "sweep.csv", "status"),
              (std::vector<std::string>{"missing", "missing", "ok", "ok"}));
  }
  const Result again =
      shell(kBin + " sweep " + study.string() + " --jobs 1 --out " + out.string(), d);
  EXPECT_EQ(again.status, 0) << again.err;
  EXPECT_EQ(count_of(again.err, ") ok,"), 2) << again.err;
  EXPECT_EQ(column(out / "sweep.csv", "status"), std::vector<std::string>(4, "ok"));
}

// Study files and options a careless user types: a byte-order mark and CRLF (refused as "line
// 1: expected key = value"), 10^6 x 10^6 members (grew past 400 MB before anything ran), a
// folder as the study file ("no study.scenario given"), options of another command (ignored).
TEST(StudyFaults, HostileStudyFilesAndOptions) {
  const fs::path d = scratch("study_files");
  const fs::path bom = d / "bom.ini";
  std::ofstream(bom) << "\xEF\xBB\xBF[study]\r\nscenario = " << kMindlin
                     << "\r\nset = grid.n=16\r\n[vary]\r\nload.amplitude = 0.3, 0.5\r\n";
  EXPECT_EQ(
      shell(kBin + " sweep " + bom.string() + " --list --out " + (d / "o").string(), d).status, 0);
  const fs::path huge = d / "huge.ini";
  std::ofstream(huge) << "[study]\nscenario = " << kMindlin
                      << "\n[vary]\nsurface.seed = linear(1, 1000000, 1000000)\n"
                         "load.amplitude = linear(0.1, 0.5, 1000000)\n";
  const struct {
    std::string args, says;
  } cases[] = {
      {"sweep " + huge.string() + " --list", "1e+12 members"},
      {"sweep " + d.string() + " --list", "not a study file"},
      {"check " + kMindlin + " --hurst 0.5", "--hurst is not an option of `fretbem check`"},
      {"run " + kMindlin + " --jobs 2", "--jobs is not an option of `fretbem run`"},
      {"sweep " + bom.string() + " --seeds 5", "--seeds is not an option of `fretbem sweep`"},
  };
  for (const auto& c : cases) {
    const Result r = shell(kBin + " " + c.args, d);
    EXPECT_EQ(r.status, 2) << c.args << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << r.err;
    EXPECT_EQ(lines(r.err), 1) << r.err;
  }
}

// A failed write never replaces the file: PATH.tmp that cannot be created (here a folder of
// that name) leaves PATH as it was, and the error names PATH.
TEST(StudyFaults, AtomicWriteKeepsThePreviousFile) {
  const fs::path d = scratch("atomic");
  const fs::path f = d / "sweep.csv";
  write_file_atomically(f, "good\n");
  EXPECT_EQ(slurp(f), "good\n");
  fs::create_directories(d / "sweep.csv.tmp");
  try {
    write_file_atomically(f, "new\n");
    ADD_FAILURE() << "accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(f.string() + ": cannot write"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(slurp(f), "good\n");
  EXPECT_THROW(write_file_atomically(d / "no" / "such" / "x.csv", "x"), std::runtime_error);
}

// A full disk (tmpfs, root only) while sweep.csv and aggregate.csv are written: exit 1, one line
// naming the file, and the last good sweep.csv kept. Before, sweep.csv became an empty file and
// aggregate.csv was cut at 5963 of 10001 rows, both with exit 0.
TEST(StudyFaults, SummariesOnAFullDiskKeepTheLastGoodVersion) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to mount a tmpfs";
  const fs::path d = scratch("full_disk"), mnt = d / "tmpfs";
  fs::create_directories(mnt);
  if (::mount("tmpfs", mnt.c_str(), "tmpfs", 0, "size=1m") != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here";
  const fs::path study = small_study(d), out = mnt / "sw";
  Result r =
      shell(kBin + " sweep " + study.string() + " --quiet --jobs 2 --out " + out.string(), d);
  EXPECT_EQ(r.status, 0) << r.err;
  const std::string good = slurp(out / "sweep.csv");
  {  // fill the disk
    std::ofstream fill(mnt / "fill", std::ios::binary);
    const std::string block(4096, 'x');
    while (fill.write(block.data(), std::streamsize(block.size()))) {
    }
  }
  r = shell(kBin + " sweep " + study.string() + " --aggregate --out " + out.string(), d);
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("sweep.csv: cannot write: No space left on device"), std::string::npos)
      << r.err;
  EXPECT_EQ(slurp(out / "sweep.csv"), good);
  EXPECT_FALSE(fs::exists(out / "sweep.csv.tmp"));
  fs::remove(mnt / "fill");
  fs::remove_all(out);
  r = shell(kBin + " ensemble " + kRough + " --hurst 0.5 --seeds 2 --bins 10000 --quiet --out " +
                (mnt / "e").string() + " --set grid.n=16 --set load.steps=3",
            d);
  const bool written = fs::exists(mnt / "e" / "aggregate.csv");
  ::umount(mnt.c_str());
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("aggregate.csv: cannot write"), std::string::npos) << r.err;
  EXPECT_FALSE(written);
}
