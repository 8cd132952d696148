// Fault tests: a full disk, SIGKILL at random points, corrupted checkpoints,
// outputs that do not belong to the checkpoint, a second run into the same --out, and
// determinism of timeseries.csv. After each fault the last good checkpoint is intact and
// --resume gives the uninterrupted run's rows (docs/reliability.md, "Fault tests").
#include <fcntl.h>
#include <gtest/gtest.h>
#include <hdf5.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "fretbem/io/checkpoint.hpp"
#include "support/child_process.hpp"
#include "support/temp_dir.hpp"
#include "support/varying_normal_table.hpp"
#include "sweep_test_util.hpp"

namespace fs = std::filesystem;

namespace {

const std::string kBin = FRETBEM_BINARY;
const std::string kScenario =
    (fs::path(FRETBEM_SOURCE_DIR) / "scenarios" / "mindlin_cycle.ini").string();
// Quick: n = 16, mindlin_cycle's 193 steps; fields and a checkpoint at every step.
const std::string kQuick =
    " --quiet --set grid.n=16 --set output.fields=pressure --set output.fields_every=1"
    " --set output.checkpoint_every=1";

const std::string kLight = " --quiet --set grid.n=16";

struct Result {
  int code = -1;  ///< exit code, or 128 + signal
  std::string err;
};

Result run(const std::string& args, const fs::path& scratch, const std::string& wrapper = "") {
  const fs::path errfile = scratch / "stderr.txt";
  const int st =
      std::system((wrapper + kBin + " " + args + " > /dev/null 2> " + errfile.string()).c_str());
  Result r;
  r.code = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
  std::ifstream in(errfile);
  std::stringstream ss;
  ss << in.rdbuf();
  r.err = ss.str();
  return r;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::vector<std::vector<std::string>> rows_of(const fs::path& csv) {
  std::vector<std::vector<std::string>> rows;
  std::ifstream in(csv);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string c;
    while (std::getline(ss, c, ',')) cells.push_back(c);
    rows.push_back(cells);
  }
  return rows;
}

// The resumed run's rows equal the uninterrupted run's: byte-equal except `convolutions`
// (work counter) and kx: the stiffness CG's warm start is not checkpointed, and two CG solves
// stopped at relative residual 1e-9 from different starts differ by up to the condition
// number times that (1.1e-8 relative seen at n = 16 after a full-disk stop): 1e-7.
// The same for any CSV of the run (cycles.csv: kx_at_max, kx_at_min as kx).
void expect_same_csv(const fs::path& a, const fs::path& b, const std::string& name) {
  const auto ra = rows_of(a / name), rb = rows_of(b / name);
  ASSERT_EQ(ra.size(), rb.size()) << name;
  const auto& cols = ra[0];
  for (std::size_t i = 1; i < ra.size(); ++i) {
    ASSERT_EQ(ra[i].size(), rb[i].size()) << name << " row " << i;
    for (std::size_t c = 0; c < cols.size(); ++c) {
      if (cols[c] == "convolutions" || ra[i][c] == rb[i][c]) continue;  // nan kx: not solved
      if (cols[c].starts_with("kx")) {
        EXPECT_NEAR(std::stod(ra[i][c]), std::stod(rb[i][c]), 1e-7 * std::abs(std::stod(ra[i][c])));
        continue;
      }
      EXPECT_EQ(ra[i][c], rb[i][c]) << name << " row " << i << " column " << cols[c];
    }
  }
}

void expect_same_rows(const fs::path& a, const fs::path& b) {
  expect_same_csv(a, b, "timeseries.csv");
  EXPECT_EQ(rows_of(a / "cycles.csv").size(), rows_of(b / "cycles.csv").size());
}

class Faults : public ::testing::Test {
 protected:
  // The uninterrupted reference run (once per test).
  fs::path full() {
    const fs::path f = dir_ / "full";
    if (!fs::exists(f)) {
      EXPECT_EQ(run("run " + kScenario + kQuick + " --out " + f.string(), dir_).code, 0);
    }
    return f;
  }
  // The same run without fields and per-step checkpoints (their fsyncs dominate a loaded
  // machine): the rows are those of full().
  fs::path light() {
    const fs::path f = dir_ / "light";
    if (!fs::exists(f)) {
      EXPECT_EQ(run("run " + kScenario + kLight + " --out " + f.string(), dir_).code, 0);
    }
    return f;
  }
  const fretbem_test::TempDir tmp_{"faults"};
  const fs::path dir_ = tmp_.path();
};

// Rewrites one double dataset of a checkpoint (1-D or 2-D, new shape allowed).
void replace_dataset(const fs::path& file, const std::string& name, const std::vector<double>& v,
                     std::vector<hsize_t> dims) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  H5Ldelete(f, name.c_str(), H5P_DEFAULT);
  const hid_t s = H5Screate_simple(int(dims.size()), dims.data(), nullptr);
  const hid_t d =
      H5Dcreate2(f, name.c_str(), H5T_IEEE_F64LE, s, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), 0);
  H5Dclose(d), H5Sclose(s);
  ASSERT_GE(H5Fclose(f), 0);
  fretbem::reseal_checkpoint(file);  // an edit on purpose: past the checksum, to the validation
}

void delete_link(const fs::path& file, const std::string& name) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  ASSERT_GE(H5Ldelete(f, name.c_str(), H5P_DEFAULT), 0);
  ASSERT_GE(H5Fclose(f), 0);
  fretbem::reseal_checkpoint(file);
}

std::vector<double> read_vector(const fs::path& file, const std::string& name) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  const hid_t s = H5Dget_space(d);
  std::vector<double> v(std::size_t(H5Sget_simple_extent_npoints(s)));
  H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Sclose(s), H5Dclose(d), H5Fclose(f);
  return v;
}

std::size_t count_groups(const fs::path& file, const std::string& group) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t g = H5Gopen2(f, group.c_str(), H5P_DEFAULT);
  H5G_info_t info{};
  H5Gget_info(g, &info);
  H5Gclose(g), H5Fclose(f);
  return info.nlinks;
}

}  // namespace

// A full disk (tmpfs of 120, 300 and 500 KiB, when root; the first fills during a checkpoint,
// the others during a result.h5 flush, which crashed at exit inside HDF5): the run stops with
// one line naming the file and exit 1, the checkpoint on disk is the last good one, and
// --resume elsewhere gives the uninterrupted run's rows.
TEST_F(Faults, FullDiskKeepsLastGoodCheckpoint) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to mount a tmpfs";
  const fs::path mnt = dir_ / "tmpfs";
  fs::create_directories(mnt);
  for (const char* size : {"size=120k", "size=300k", "size=500k"}) {
    SCOPED_TRACE(size);
    if (::mount("tmpfs", mnt.c_str(), "tmpfs", 0, size) != 0)
      GTEST_SKIP() << "cannot mount a tmpfs here";
    const Result r = run("run " + kScenario + kQuick + " --out " + (mnt / "r").string(), dir_);
    const fs::path moved = dir_ / ("moved_" + std::string(size));
    fs::copy(mnt / "r", moved);
    ::umount(mnt.c_str());
    EXPECT_EQ(r.code, 1) << r.err;
    EXPECT_NE(r.err.find(mnt.string()), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(moved / "checkpoint.h5.tmp"));
    ASSERT_TRUE(fs::exists(moved / "checkpoint.h5"));
    fs::remove(moved / ".fretbem.lock");
    ASSERT_EQ(run("run --resume " + moved.string() + " --quiet", dir_).code, 0);
    expect_same_rows(full(), moved);
  }
}

// Mounts at `mnt` a tmpfs with room for the files of `folder` and `extra_kib` KiB more (root
// only); false when it cannot.
bool mount_room_for(const fs::path& folder, std::uintmax_t extra_kib, const fs::path& mnt) {
  std::uintmax_t bytes = 0;
  for (const auto& e : fs::directory_iterator(folder)) bytes += fs::file_size(e.path());
  fs::create_directories(mnt);
  const std::string size = "size=" + std::to_string(bytes / 1024 + extra_kib) + "k";
  return ::mount("tmpfs", mnt.c_str(), "tmpfs", 0, size.c_str()) == 0;
}

// A resume on a disk too full to rebuild result.h5 stops with one line and exit 1 (it crashed
// inside HDF5) and leaves the run's files as they were.
TEST_F(Faults, ResumeOnFullDiskLeavesTheRunAsItWas) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to mount a tmpfs";
  const fs::path part = dir_ / "part", mnt = dir_ / "tmpfs";
  ASSERT_EQ(
      run("run " + kScenario + kQuick + " --stop-after 150 --out " + part.string(), dir_).code, 0);
  if (!mount_room_for(part, 40, mnt)) GTEST_SKIP() << "cannot mount a tmpfs here";
  fs::copy(part, mnt / "r");
  const std::string before = slurp(mnt / "r" / "result.h5");
  const Result r = run("run --resume " + (mnt / "r").string() + " --quiet", dir_);
  const std::string after = slurp(mnt / "r" / "result.h5");
  const bool leftover = fs::exists(mnt / "r" / "result.h5.resume");
  ::umount(mnt.c_str());
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_TRUE(before == after);
  EXPECT_FALSE(leftover);
}

// SIGKILL at six random points (fixed seed) of a fields-every-step run: each time the
// checkpoint is whole and --resume gives the uninterrupted run's rows, in timeseries.csv and
// in result.h5, with a field group for every step. A kill inside an HDF5 flush can tear
// result.h5 in ways found only at the next write (1 kill in ~24 before resume rebuilt it).
TEST_F(Faults, KillAtRandomPointsResumes) {
  std::mt19937 rng(14);
  std::uniform_int_distribution<int> rows_before_kill(3, 150);
  const fs::path ref = full();
  const auto steps = rows_of(ref / "timeseries.csv").size() - 1;
  for (int trial = 0; trial < 6; ++trial) {
    const fs::path part = dir_ / ("kill" + std::to_string(trial));
    const std::size_t at = std::size_t(rows_before_kill(rng));
    const std::string out = part.string();
    const pid_t pid = fork();
    if (pid == 0) {
      execl(kBin.c_str(), kBin.c_str(), "run", kScenario.c_str(), "--quiet", "--set", "grid.n=16",
            "--set", "output.fields=pressure", "--set", "output.fields_every=1", "--set",
            "output.checkpoint_every=1", "--out", out.c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
    int status = 0;
    ASSERT_TRUE(fretbem_test::wait_until(
        pid, [&] { return rows_of(part / "timeseries.csv").size() >= at + 1; }, &status))
        << "the run ended before row " << at;
    kill(pid, SIGKILL);
    waitpid(pid, &status, 0);
    ASSERT_TRUE(fs::exists(part / "checkpoint.h5")) << "kill after " << at << " rows";
    const Result r = run("run --resume " + out + " --quiet", dir_);
    ASSERT_EQ(r.code, 0) << "kill after " << at << " rows: " << r.err;
    expect_same_rows(ref, part);
    const auto rows = rows_of(part / "timeseries.csv");
    EXPECT_EQ(read_vector(part / "result.h5", "timeseries").size(),
              (rows.size() - 1) * rows.front().size());
    // A kill that tore the /fields group table can cost groups written before the checkpoint
    // (measured: 1 kill in 120, 66 of 177 groups); such a loss is always announced.
    if (r.err.find("rebuilt from timeseries.csv") == std::string::npos)
      EXPECT_EQ(count_groups(part / "result.h5", "/fields"), steps) << r.err;
    else
      EXPECT_LE(count_groups(part / "result.h5", "/fields"), steps) << r.err;
  }
}

// SIGTERM (Slurm at a time limit) and SIGINT (Ctrl-C) stop a run after the step in progress
// with its checkpoint written: exit 128 + signal, one line on stderr saying how to continue,
// and --resume gives the uninterrupted run's rows. The signal is pending when the run starts
// (its step 0, the normal loading, still runs: a checkpoint before it holds nothing to
// resume), and when a resume of 40 finished steps (--stop-after) starts: both stop points are
// exact, whatever the machine's load.
TEST_F(Faults, SignalStopsRunWithCheckpoint) {
  const fs::path ref = light();
  for (const int sig : {SIGTERM, SIGINT}) {
    const fs::path part = dir_ / ("signal" + std::to_string(sig)), err = dir_ / "signal.err";
    const auto stop = [&](std::vector<std::string> args, const std::string& where) {
      args.insert(args.begin(), kBin);
      const int code = fretbem_test::wait_exit(
          fretbem_test::spawn_with_pending_signal(sig, args, dir_ / "signal.out", err));
      const std::string text = slurp(err);
      EXPECT_EQ(code, 128 + sig) << text;
      EXPECT_NE(text.find(std::string(sig == SIGTERM ? "stopped by SIGTERM" : "stopped by SIGINT") +
                          " after " + where),
                std::string::npos)
          << text;
      EXPECT_NE(text.find("--resume " + part.string()), std::string::npos) << text;
    };
    stop({"run", kScenario, "--quiet", "--set", "grid.n=16", "--out", part.string()},
         "1 of 193 steps");
    ASSERT_EQ(run("run --resume " + part.string() + " --quiet --stop-after 39", dir_).code, 0);
    stop({"run", "--resume", part.string(), "--quiet"}, "40 of 193 steps");
    ASSERT_EQ(run("run --resume " + part.string() + " --quiet", dir_).code, 0);
    expect_same_rows(ref, part);
  }
}

// An input file edited between a run and its --resume (a load table, a height map) is refused
// with one line naming the key and file; restored, the resume runs (it was followed silently:
// the resumed steps took the edited table's loads).
TEST_F(Faults, EditedInputFilesAreRefusedOnResume) {
  const fs::path src = fs::path(FRETBEM_SOURCE_DIR) / "scenarios", d = dir_ / "edit";
  fs::create_directories(d);
  fs::copy_file(src / "varying_normal.ini", d / "v.ini");
  fs::copy_file(src / "varying_normal.csv", d / "varying_normal.csv");
  std::string map;  // a paraboloid cap, R = 10 mm, on mindlin_cycle's 16 x 16 grid
  for (int j = 0; j < 16; ++j, map += '\n')
    for (int i = 0; i < 16; ++i) {
      const double h = 2.8e-4 / 16, x = (i - 7.5) * h, y = (j - 7.5) * h;
      map += std::to_string(-(x * x + y * y) / 0.02 * 1e6) + "e-6 ";
    }
  std::ofstream(d / "h.txt") << map;
  const std::string table = "run " + (d / "v.ini").string() + " --quiet --set grid.n=16";
  const std::string surface = "run " + kScenario +
                              " --quiet --set grid.n=16 --set surface.type=file --set "
                              "surface.file=" +
                              (d / "h.txt").string();
  struct Case {
    std::string run, key;
    fs::path file;
  };
  for (const Case& c : {Case{table, "load.table", d / "varying_normal.csv"},
                        Case{surface, "surface.file", d / "h.txt"}}) {
    const fs::path out = d / c.key;
    ASSERT_EQ(run(c.run + " --stop-after 3 --out " + out.string(), dir_).code, 0) << c.key;
    const std::string original = slurp(c.file);
    std::string edited = original;
    edited[edited.find('\n') + 3] = edited[edited.find('\n') + 3] == '1' ? '2' : '1';
    std::ofstream(c.file, std::ios::trunc) << edited;
    const Result r = run("run --resume " + out.string() + " --quiet", dir_);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find(c.key + " = " + c.file.string()), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    std::ofstream(c.file, std::ios::trunc) << original;
    EXPECT_EQ(run("run --resume " + out.string() + " --quiet", dir_).code, 0) << c.key;
  }
}

// A result.h5 torn mid-flush (here: cut to half its bytes, which HDF5 cannot open) is rebuilt
// on resume from timeseries.csv and the checkpoint, the damaged file kept beside; the rows are
// the uninterrupted run's. With timeseries.csv cut as well, resume refuses naming it.
TEST_F(Faults, TornResultFileIsRebuiltOnResume) {
  const fs::path part = dir_ / "part", both = dir_ / "both";
  ASSERT_EQ(run("run " + kScenario + kQuick + " --stop-after 30 --out " + part.string(), dir_).code,
            0);
  fs::copy(part, both);
  fs::resize_file(part / "result.h5", fs::file_size(part / "result.h5") / 2);
  const Result r = run("run --resume " + part.string() + " --quiet", dir_);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("rebuilt from timeseries.csv"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(part / "result.h5.damaged"));
  const fs::path ref = full();
  expect_same_rows(ref, part);
  const auto rows = rows_of(ref / "timeseries.csv");
  EXPECT_EQ(read_vector(part / "result.h5", "timeseries").size(),
            (rows.size() - 1) * rows.front().size());

  fs::resize_file(both / "result.h5", fs::file_size(both / "result.h5") / 2);
  // The header, 5 rows and a torn sixth.
  const std::string text = slurp(both / "timeseries.csv");
  std::size_t cut = 0;
  for (int i = 0; i < 6; ++i) cut = text.find('\n', cut) + 1;
  std::ofstream(both / "timeseries.csv", std::ios::trunc) << text.substr(0, cut + 5);
  const Result bad = run("run --resume " + both.string() + " --quiet", dir_);
  EXPECT_EQ(bad.code, 2) << bad.err;
  EXPECT_NE(bad.err.find("timeseries.csv"), std::string::npos) << bad.err;
  EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
}

namespace {

// A damage done to a copy of a good checkpoint, and what the refusal must name.
struct CheckpointDamage {
  std::string name, expect;
  std::function<void(const fs::path&)> damage;
};

// Damages to the file's bytes, made from the good checkpoint's `bytes`.
std::vector<CheckpointDamage> damaged_bytes(const std::string& bytes, std::mt19937& rng) {
  return {
      {"truncated", "checkpoint.h5",
       [&](const fs::path& p) {
         std::ofstream(p, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
       }},
      {"zeros", "damaged checkpoint",
       [&](const fs::path& p) {
         std::ofstream(p, std::ios::binary) << std::string(bytes.size(), '\0');
       }},
      {"one flipped bit", "checksum mismatch",
       [&](const fs::path& p) {
         std::string b = bytes;
         b[b.size() / 2] ^= 4;
         std::ofstream(p, std::ios::binary) << b;
       }},
      // Written before the checksum block (bare HDF5), damaged so that HDF5 1.10.8 itself dies
      // with SIGSEGV reading it (found by fuzz_checkpoint): refused, not a crash.
      {"unsealed, HDF5 dies on it", "HDF5 died",
       [&](const fs::path& p) {
         fs::copy_file(
             fs::path(FRETBEM_SOURCE_DIR) / "tests/bad_inputs/data/checkpoint_hdf5_segv.h5", p,
             fs::copy_options::overwrite_existing);
       }},
      {"flipped bytes", "checkpoint.h5",
       [&](const fs::path& p) {
         std::string b = bytes;
         for (std::size_t k = 0; k < b.size(); k += 1 + rng() % 97) b[k] = char(rng());
         std::ofstream(p, std::ios::binary) << b;
       }},
  };
}

// Damages to single datasets of a readable checkpoint: values out of range, fields of another
// grid, formats of another version.
std::vector<CheckpointDamage> damaged_datasets() {
  return {
      {"components 0", "scalars[4]",
       [](const fs::path& p) {
         auto s = read_vector(p, "scalars");
         s[4] = 0;
         replace_dataset(p, "scalars", s, {5});
       }},
      {"components -1", "scalars[4]",
       [](const fs::path& p) {
         auto s = read_vector(p, "scalars");
         s[4] = -1;
         replace_dataset(p, "scalars", s, {5});
       }},
      {"next_step -5", "next_step",
       [](const fs::path& p) {
         auto m = read_vector(p, "memory");
         m[0] = -5;
         replace_dataset(p, "memory", m, {6});
       }},
      {"next_step NaN", "memory",
       [](const fs::path& p) {
         auto m = read_vector(p, "memory");
         m[0] = NAN;
         replace_dataset(p, "memory", m, {6});
       }},
      {"next_step past the end", "next_step",
       [](const fs::path& p) {
         auto m = read_vector(p, "memory");
         m[0] = 1e6;
         replace_dataset(p, "memory", m, {6});
       }},
      {"pressure of another grid", "pressure",
       [](const fs::path& p) {
         replace_dataset(p, "pressure", std::vector<double>(64, 0.0), {8, 8});
       }},
      {"infinite traction", "traction0",
       [](const fs::path& p) {
         auto t = read_vector(p, "traction0");
         t[5] = INFINITY;
         replace_dataset(p, "traction0", t, {16, 16});
       }},
      {"bound of another grid", "memory_field_bound",
       [](const fs::path& p) {
         replace_dataset(p, "memory_field_bound", std::vector<double>(64, 0.0), {8, 8});
       }},
      {"negative bound", "memory_field_bound",
       [](const fs::path& p) {
         auto g = read_vector(p, "memory_field_bound");
         g[7] = -1.0;
         replace_dataset(p, "memory_field_bound", g, {16, 16});
       }},
      {"state 4", "state holds 4",
       [](const fs::path& p) {
         auto st = read_vector(p, "state");
         st[3] = 4.0;
         replace_dataset(p, "state", st, {16, 16});
       }},
      {"last_target overlong", "last_target",
       [](const fs::path& p) {
         replace_dataset(p, "last_target", {1e9, 0.0}, {2});
       }},
      {"old format", "checkpoint_format",
       [](const fs::path& p) { replace_dataset(p, "checkpoint_format", {1.0}, {1}); }},
      {"old format, old name", "format_version",
       [](const fs::path& p) {
         delete_link(p, "checkpoint_format");
         replace_dataset(p, "format_version", {1.0}, {1});
       }},
  };
}

}  // namespace

// Damaged checkpoints: exit 2 naming checkpoint.h5 (and the quantity), outputs untouched.
TEST_F(Faults, CorruptedCheckpointsAreRefused) {
  const fs::path good = dir_ / "good";
  ASSERT_EQ(run("run " + kScenario + kQuick + " --stop-after 20 --out " + good.string(), dir_).code,
            0);
  const std::string csv = slurp(good / "timeseries.csv");
  const std::string bytes = slurp(good / "checkpoint.h5");
  std::mt19937 rng(14);
  std::vector<CheckpointDamage> cases = damaged_bytes(bytes, rng);
  for (CheckpointDamage& c : damaged_datasets()) cases.push_back(std::move(c));
  for (const auto& c : cases) {
    const fs::path d = dir_ / "bad";
    fs::remove_all(d);
    fs::copy(good, d);
    c.damage(d / "checkpoint.h5");
    const Result r = run("run --resume " + d.string() + " --quiet", dir_);
    EXPECT_EQ(r.code, 2) << c.name << ": " << r.err;
    EXPECT_NE(r.err.find("checkpoint.h5"), std::string::npos) << c.name << ": " << r.err;
    EXPECT_NE(r.err.find(c.expect), std::string::npos) << c.name << ": " << r.err;
    EXPECT_EQ(slurp(d / "timeseries.csv"), csv) << c.name << ": outputs were touched";
  }
}

// Checkpoints written before the format dataset was renamed (dataset format_version = 2, the
// same layout) still resume, to the uninterrupted run's rows.
TEST_F(Faults, CheckpointWithOldFormatNameResumes) {
  const fs::path part = dir_ / "part";
  ASSERT_EQ(run("run " + kScenario + kQuick + " --stop-after 20 --out " + part.string(), dir_).code,
            0);
  delete_link(part / "checkpoint.h5", "checkpoint_format");
  replace_dataset(part / "checkpoint.h5", "format_version", {2.0}, {1});
  // Written before the checksum block: the bare HDF5 file, read unchecked.
  const std::string bytes = slurp(part / "checkpoint.h5");
  std::ofstream(part / "checkpoint.h5", std::ios::binary | std::ios::trunc) << bytes.substr(512);
  ASSERT_EQ(bytes.compare(512, 4, "\x89HDF"), 0);
  const Result r = run("run --resume " + part.string() + " --quiet", dir_);
  ASSERT_EQ(r.code, 0) << r.err;
  expect_same_rows(full(), part);
}

namespace {

// DIR/NAME.csv without its last column, as a fretbem without that column wrote it.
void drop_last_csv_column(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line, kept;
  while (std::getline(in, line)) kept += line.substr(0, line.rfind(',')) + "\n";
  in.close();
  std::ofstream(csv, std::ios::trunc) << kept;
}

// result.h5's /timeseries without its last column (a plain 2-D dataset, as an extendable one
// reads the same).
void drop_last_timeseries_column(const fs::path& h5) {
  const hid_t f = H5Fopen(h5.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const hid_t d = H5Dopen2(f, "timeseries", H5P_DEFAULT);
  const hid_t s = H5Dget_space(d);
  hsize_t dims[2] = {0, 0};
  H5Sget_simple_extent_dims(s, dims, nullptr);
  std::vector<double> all(dims[0] * dims[1]), kept;
  H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, all.data());
  H5Sclose(s), H5Dclose(d);
  for (hsize_t r = 0; r < dims[0]; ++r)
    kept.insert(kept.end(), all.begin() + long(r * dims[1]),
                all.begin() + long((r + 1) * dims[1] - 1));
  H5Ldelete(f, "timeseries", H5P_DEFAULT);
  const hsize_t shape[2] = {dims[0], dims[1] - 1};
  const hid_t s2 = H5Screate_simple(2, shape, nullptr);
  const hid_t d2 =
      H5Dcreate2(f, "timeseries", H5T_IEEE_F64LE, s2, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(H5Dwrite(d2, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, kept.data()), 0);
  H5Dclose(d2), H5Sclose(s2);
  ASSERT_GE(H5Fclose(f), 0);
}

}  // namespace

// A run stopped by a fretbem without the step_error column (load.tolerance) resumes: its rows
// get step_error 0, the value of a run without step control, the files are continued under
// today's header, the saved fields are kept, and the rows are the uninterrupted run's.
TEST_F(Faults, RunStoppedBeforeTheStepErrorColumnResumes) {
  const fs::path part = dir_ / "part";
  ASSERT_EQ(run("run " + kScenario + kQuick + " --stop-after 20 --out " + part.string(), dir_).code,
            0);
  ASSERT_EQ(rows_of(part / "timeseries.csv")[0].back(), "step_error");
  drop_last_csv_column(part / "timeseries.csv");
  drop_last_csv_column(part / "cycles.csv");
  drop_last_timeseries_column(part / "result.h5");
  const Result r = run("run --resume " + part.string() + " --quiet", dir_);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err.find("rebuilt"), std::string::npos) << r.err;  // result.h5 was whole
  EXPECT_FALSE(fs::exists(part / "result.h5.damaged"));
  expect_same_rows(full(), part);
  expect_same_csv(full(), part, "cycles.csv");
  EXPECT_EQ(count_groups(part / "result.h5", "/fields"),
            count_groups(full() / "result.h5", "/fields"));
  EXPECT_FALSE(fs::exists(part / "timeseries.resume.csv"));
}

// A bound that moves with the state (static_kinetic at a varying normal load; evolving
// friction under Coupling::coupled): the step's dissipation quadrature starts from the bound
// the last step ended with, which is not recomputable from the state after it. The resumed
// rows, dissipation included, are the uninterrupted run's.
TEST_F(Faults, ResumeKeepsTheBoundOfTheLastStep) {
  const fs::path table = dir_ / "T2.csv";
  fretbem_test::write_varying_normal_table(table);
  const fs::path src(FRETBEM_SOURCE_DIR);
  const std::string kinetic = (src / "scenarios" / "varying_normal.ini").string() +
                              " --quiet --set grid.n=32 --set load.table=" + table.string() +
                              " --set friction.law=static_kinetic --set friction.mu_kinetic=0.4";
  const std::string coupled =
      (src / "scenarios" / "mindlin_cycle.ini").string() +
      " --quiet --set grid.n=32 --set load.cycles=1 --set load.steps_per_cycle=16"
      " --set solver.coupling=coupled --set friction.law=evolving --set friction.mu_final=0.7"
      " --set friction.scale=1";
  for (const auto& [args, stop] : {std::pair{kinetic, 6}, std::pair{coupled, 1}}) {
    const fs::path whole = dir_ / ("whole" + std::to_string(stop));
    const fs::path part = dir_ / ("part" + std::to_string(stop));
    ASSERT_EQ(run("run " + args + " --out " + whole.string(), dir_).code, 0);
    ASSERT_EQ(
        run("run " + args + " --stop-after " + std::to_string(stop) + " --out " + part.string(),
            dir_)
            .code,
        0);
    const Result r = run("run --resume " + part.string() + " --quiet", dir_);
    ASSERT_EQ(r.code, 0) << r.err;
    expect_same_rows(whole, part);
    expect_same_csv(whole, part, "cycles.csv");
  }
}

// A coupled (Dundurs beta != 0) erk wear run: the normal loading that measures the unworn
// indentation (the wear tolerances' scale) slips and does work, and a resumed run probes it
// again; a resumed run's dissipation equals the uninterrupted run's (sweep seed 1 case 274:
// 2.1e-4 relative above it from the first resumed row).
TEST_F(Faults, ResumedCoupledOdeWearRunKeepsItsDissipation) {
  const fs::path scenario = dir_ / "coupled_wear.ini";
  std::ofstream(scenario)
      << "[material]\nE = 5e9\nnu = 0.3\nmu = 0.5\n[grid]\nn = 16\nlength = 2.8e-4\n"
         "[surface]\ntype = sphere\nradius = 0.01\n[load]\npath = sine\n"
         "control = displacement\nnormal_force = 0.25\ndisplacement_amplitude = 3e-7\n"
         "direction = -45\n[solver]\nstiffness = false\ncoupling = coupled\n[wear]\n"
         "law = archard\nintegrator = erk\ncycles = 30\ncoefficient = 5e-13\nrtol = 0.01\n";
  const fs::path whole = dir_ / "whole", part = dir_ / "part";
  const std::string args = "run " + scenario.string() + " --quiet --out ";
  ASSERT_EQ(run(args + whole.string(), dir_).code, 0);
  ASSERT_EQ(run(args + part.string() + " --stop-after 2", dir_).code, 0);
  const Result r = run("run --resume " + part.string() + " --quiet", dir_);
  ASSERT_EQ(r.code, 0) << r.err;
  expect_same_rows(whole, part);
  expect_same_csv(whole, part, "cycles.csv");
}

// Outputs that do not belong to the checkpoint are refused, not patched.
TEST_F(Faults, DamagedOrForeignOutputsAreRefused) {
  const fs::path good = dir_ / "good", other = dir_ / "other";
  ASSERT_EQ(run("run " + kScenario + kQuick + " --stop-after 30 --out " + good.string(), dir_).code,
            0);
  ASSERT_EQ(
      run("run " + kScenario + kQuick + " --stop-after 30 --out " + other.string(), dir_).code, 0);
  const std::string csv = slurp(good / "timeseries.csv");
  struct Case {
    std::string name, expect;
    std::function<void(const fs::path&)> damage;
  };
  const std::vector<Case> cases{
      {"deleted csv", "timeseries.csv",
       [](const fs::path& d) { fs::remove(d / "timeseries.csv"); }},
      {"emptied csv", "timeseries.csv",
       [](const fs::path& d) { std::ofstream(d / "timeseries.csv", std::ios::trunc); }},
      {"truncated csv", "timeseries.csv",
       [&](const fs::path& d) {
         std::ofstream(d / "timeseries.csv", std::ios::trunc) << csv.substr(0, csv.size() / 2);
       }},
      {"garbage row", "timeseries.csv",
       [&](const fs::path& d) {
         std::string b = csv;
         const std::size_t at = b.find('\n', b.size() / 2) + 1;
         for (std::size_t k = 0; k < 5; ++k) b[at + k] = "xx,yy"[k];
         std::ofstream(d / "timeseries.csv", std::ios::trunc) << b;
       }},
      {"changed value", "differs from result.h5",
       [&](const fs::path& d) {
         std::string b = csv;
         const auto at = b.find("\n10,") + 4;
         b[at] = b[at] == '9' ? '8' : '9';
         std::ofstream(d / "timeseries.csv", std::ios::trunc) << b;
       }},
      {"result.h5 of another run", "run id",
       [&](const fs::path& d) {
         fs::copy_file(other / "result.h5", d / "result.h5", fs::copy_options::overwrite_existing);
       }},
      {"result.h5 deleted", "result.h5", [](const fs::path& d) { fs::remove(d / "result.h5"); }},
  };
  for (const auto& c : cases) {
    const fs::path d = dir_ / "bad";
    fs::remove_all(d);
    fs::copy(good, d);
    c.damage(d);
    const Result r = run("run --resume " + d.string() + " --quiet", dir_);
    EXPECT_EQ(r.code, 2) << c.name << ": " << r.err;
    EXPECT_NE(r.err.find(c.expect), std::string::npos) << c.name << ": " << r.err;
  }
}

// A second run into a directory holding a run's results is refused unless --overwrite; with
// it, the old checkpoint is gone (a later --resume cannot mix the two runs).
TEST_F(Faults, SecondRunIntoSameOutNeedsOverwrite) {
  const fs::path d = dir_ / "r";
  const std::string cmd = "run " + kScenario + " --quiet --set grid.n=16 --out " + d.string();
  ASSERT_EQ(run(cmd + " --stop-after 5", dir_).code, 0);
  const std::string before = slurp(d / "timeseries.csv");
  const Result again = run(cmd, dir_);
  EXPECT_EQ(again.code, 2);
  EXPECT_NE(again.err.find("--overwrite"), std::string::npos) << again.err;
  EXPECT_EQ(slurp(d / "timeseries.csv"), before);
  // A run refused by its scenario (bad key value) with --overwrite leaves the old checkpoint
  // of the old outputs; a run that starts replaces it.
  ASSERT_EQ(run(cmd + " --overwrite --stop-after 2", dir_).code, 0);
  EXPECT_EQ(rows_of(d / "timeseries.csv").size(), 3u);  // header + steps 0, 1
  EXPECT_EQ(run("run --resume " + d.string() + " --quiet", dir_).code, 0);
  // An empty directory is fine.
  fs::create_directories(dir_ / "empty");
  EXPECT_EQ(run("run " + kScenario + " --quiet --set grid.n=16 --stop-after 1 --out " +
                    (dir_ / "empty").string(),
                dir_)
                .code,
            0);
}

// Small CLI refusals: an empty --out, and --out beside --resume.
TEST_F(Faults, OutOptionsAreChecked) {
  EXPECT_EQ(run("run " + kScenario + " --quiet --out \"\"", dir_).code, 2);
  const fs::path d = dir_ / "r";
  ASSERT_EQ(
      run("run " + kScenario + " --quiet --set grid.n=16 --stop-after 3 --out " + d.string(), dir_)
          .code,
      0);
  const Result r = run("run --resume " + d.string() + " --out " + (dir_ / "x").string(), dir_);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--out"), std::string::npos) << r.err;
}

// Two runs into one --out at once (without the lock the second would truncate the first's
// timeseries.csv): while one process holds the folder's lock, a run and a resume into it are
// refused naming the folder, and nothing in it is touched; after release both go ahead.
TEST_F(Faults, ConcurrentRunsIntoOneOutAreRefused) {
  const fs::path d = dir_ / "r";
  ASSERT_EQ(
      run("run " + kScenario + " --quiet --set grid.n=16 --stop-after 3 --out " + d.string(), dir_)
          .code,
      0);
  const std::string csv = slurp(d / "timeseries.csv");
  const int fd = ::open((d / ".fretbem.lock").c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);  // "another run" holds the folder
  for (const std::string& cmd :
       {"run " + kScenario + " --quiet --set grid.n=16 --overwrite --out " + d.string(),
        "run --resume " + d.string() + " --quiet"}) {
    const Result r = run(cmd, dir_);
    EXPECT_EQ(r.code, 2) << cmd << r.err;
    EXPECT_NE(r.err.find("another fretbem run is writing"), std::string::npos) << r.err;
  }
  EXPECT_EQ(slurp(d / "timeseries.csv"), csv);
  EXPECT_TRUE(fs::exists(d / "checkpoint.h5"));
  ::close(fd);
  EXPECT_EQ(run("run --resume " + d.string() + " --quiet", dir_).code, 0);
}

// Ensembles: a repeated Hurst exponent and an absurd bin count are refused before any member
// runs.
TEST_F(Faults, EnsembleRefusesDuplicateHurstAndHugeBins) {
  const std::string base =
      "ensemble " + kScenario + " --seeds 1 --quiet --out " + (dir_ / "e").string();
  Result r = run(base + " --hurst 0.5,0.5", dir_);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("listed twice"), std::string::npos) << r.err;
  r = run(base + " --hurst 0.5 --bins 100000000", dir_);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--bins"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "e" / "aggregate.csv"));
}

// SIGTERM to the ensemble parent: the running member ends, no further one
// starts, the finished ones are kept in members.csv and aggregate.csv, exit 143.
TEST_F(Faults, EnsembleSigtermKeepsFinishedMembers) {
  const fs::path out = dir_ / "e";
  const std::string rough =
      (fs::path(FRETBEM_SOURCE_DIR) / "scenarios" / "rough_monotone.ini").string();
  const pid_t pid = fork();
  if (pid == 0) {
    const std::string log = (dir_ / "ensemble.err").string();
    if (!freopen(log.c_str(), "w", stderr)) _exit(127);
    execl(kBin.c_str(), kBin.c_str(), "ensemble", rough.c_str(), "--hurst", "0.3,0.5,0.7",
          "--seeds", "1", "--jobs", "1", "--quiet", "--out", out.c_str(), "--set", "grid.n=32",
          "--set", "load.steps=400", nullptr);
    _exit(127);
  }
  // Members run one at a time: the second one's directory appears when the first has ended.
  int status = 0;
  ASSERT_TRUE(fretbem_test::wait_until(
      pid, [&] { return fs::exists(out / "H0.5" / "seed_001" / "log.txt"); }, &status))
      << slurp(dir_ / "ensemble.err");
  kill(pid, SIGTERM);
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status)) << "signal " << WTERMSIG(status) << slurp(dir_ / "ensemble.err");
  EXPECT_EQ(WEXITSTATUS(status), 143) << slurp(dir_ / "ensemble.err");
  const auto members = rows_of(out / "members.csv");
  ASSERT_EQ(members.size(), 4u);  // header + 3
  EXPECT_EQ(members[1][3], "0");  // finished before the signal: kept
  EXPECT_NE(members[3][3], "0");  // never finished
  const auto aggregate = rows_of(out / "aggregate.csv");
  ASSERT_GT(aggregate.size(), 1u);
  EXPECT_EQ(aggregate[1][0], "0.3");
  EXPECT_EQ(aggregate[1][5], "1");  // one member (H = 0.3) in the aggregate
  // No member process is left behind: the ensemble waited for the one it stopped.
  EXPECT_NE(slurp(dir_ / "ensemble.err").find("stopped by a signal"), std::string::npos);
}

// Table runs: `cycle` is the integer part of time, negative times too;
// cycles.csv has a row per cycle also before time 0 (it was empty); a cycle without a
// minimum turning point reports kx at its smallest F_x (it reported 0).
TEST_F(Faults, TableCyclesFollowTime) {
  const fs::path ini = dir_ / "table.ini", table = dir_ / "path.csv";
  std::ofstream(ini) << "[material]\nE = 210e9\nnu = 0.3\nmu = 0.5\n[grid]\nn = 16\n"
                        "length = 2.8e-4\n[surface]\ntype = sphere\nradius = 0.01\n"
                        "[load]\npath = table\ntable = path.csv\n";
  std::ofstream(table) << "time,Fz,Fx\n-1,10,0\n-0.75,10,2\n-0.5,10,0\n-0.25,10,-2\n0,10,0\n"
                          "0.25,10,2\n0.5,10,0\n0.75,10,-2\n1,10,0\n";
  ASSERT_EQ(run("run " + ini.string() + " --quiet --out " + (dir_ / "a").string(), dir_).code, 0);
  const auto ts = rows_of(dir_ / "a" / "timeseries.csv");
  ASSERT_EQ(ts.size(), 10u);
  ASSERT_EQ(ts[0][2], "cycle");
  const std::vector<std::string> cycle{"-1", "-1", "-1", "-1", "0", "0", "0", "0", "1"};
  for (std::size_t k = 0; k < cycle.size(); ++k) EXPECT_EQ(ts[k + 1][2], cycle[k]) << k;
  const auto cy = rows_of(dir_ / "a" / "cycles.csv");
  ASSERT_EQ(cy.size(), 3u);
  EXPECT_EQ(cy[1][0], "-1");
  EXPECT_EQ(cy[1][1], "4");
  EXPECT_EQ(cy[2][0], "0");

  // Rising only: the last step is the (maximum) turning point; no minimum turning point.
  std::ofstream(table, std::ios::trunc) << "time,Fz,Fx\n0,10,0\n0.5,10,1\n1,10,2\n";
  ASSERT_EQ(run("run " + ini.string() + " --quiet --out " + (dir_ / "b").string(), dir_).code, 0);
  const auto tb = rows_of(dir_ / "b" / "timeseries.csv");
  const auto cb = rows_of(dir_ / "b" / "cycles.csv");
  ASSERT_EQ(cb.size(), 2u);
  const auto col = [](const std::vector<std::vector<std::string>>& t, const std::string& name) {
    return std::size_t(std::find(t[0].begin(), t[0].end(), name) - t[0].begin());
  };
  EXPECT_EQ(cb[1][col(cb, "kx_at_min")], tb[2][col(tb, "kx")]);  // the step with Fx = 1
  EXPECT_EQ(cb[1][col(cb, "kx_at_max")], tb[3][col(tb, "kx")]);  // the turning point, Fx = 2
  EXPECT_GT(std::stod(cb[1][col(cb, "kx_at_min")]), 0.0);
}

// Step counts that pass the key ranges but cannot fit in memory are refused by `check` and
// `run` with the key named (load.steps = 2^30 must not end in bad_alloc).
TEST_F(Faults, HugeStepCountsAreRefused) {
  for (const std::string cmd : {"check ", "run "}) {
    const Result r =
        run(cmd + kScenario + " --quiet --set load.path=ramp --set load.steps=1073741824 --out " +
                (dir_ / "s").string(),
            dir_);
    EXPECT_EQ(r.code, 2) << cmd << r.err;
    EXPECT_NE(r.err.find("load.steps"), std::string::npos) << cmd << r.err;
  }
}

// Determinism: the same scenario gives a byte-identical timeseries.csv run after run and with
// 1 or 2 FFT threads (n = 32, the first 40 steps; docs/reliability.md).
TEST_F(Faults, TimeseriesIsByteIdenticalAcrossRunsAndThreads) {
  const std::string cmd = "run " + kScenario + " --quiet --stop-after 40 --set grid.n=32 --out ";
  ASSERT_EQ(run(cmd + (dir_ / "a").string() + " --set solver.threads=1", dir_).code, 0);
  ASSERT_EQ(run(cmd + (dir_ / "b").string() + " --set solver.threads=1", dir_).code, 0);
  ASSERT_EQ(run(cmd + (dir_ / "c").string() + " --set solver.threads=2", dir_).code, 0);
  const std::string a = slurp(dir_ / "a" / "timeseries.csv");
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, slurp(dir_ / "b" / "timeseries.csv"));
  EXPECT_EQ(a, slurp(dir_ / "c" / "timeseries.csv"));
}

// Every file of a run folder, by name, with its bytes.
std::map<std::string, std::string> folder_bytes(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::directory_iterator(dir))
    out[e.path().filename().string()] = e.is_regular_file() ? slurp(e.path()) : "(not a file)";
  return out;
}

// The run files of a folder, by name, with their bytes: the folders a replacement keeps
// beside them (.fretbem-failed, .fretbem-replaced) and the lock left out.
std::map<std::string, std::string> run_files(const fs::path& dir) {
  auto out = folder_bytes(dir);
  for (const char* other : {".fretbem-failed", ".fretbem-replaced", ".fretbem.lock"})
    out.erase(other);
  return out;
}

// A table run of a sphere whose normal force jumps at its last row (step 4) so far that the
// contact reaches the grid edge: it fails (exit 2) after checkpoints at steps 0 to 3.
std::string late_failing_run(const fs::path& scratch) {
  const fs::path ini = scratch / "late.ini";
  std::ofstream(ini) << "[material]\nE = 210e9\nnu = 0.3\nmu = 0.5\n[grid]\nn = 16\n"
                        "length = 2.8e-4\n[surface]\ntype = sphere\nradius = 0.01\n"
                        "[load]\npath = table\ntable = late.csv\n[output]\ncheckpoint_every = 1\n";
  std::ofstream(scratch / "late.csv")
      << "time,Fz,Fx\n0,10,0\n0.25,10,2\n0.5,10,0\n0.75,10,-2\n1,2000,0\n";
  return "run " + ini.string() + " --quiet";
}

// A run with --overwrite that fails leaves the results it was to replace as they were, byte
// for byte, and its own files in DIR/.fretbem-failed, the error line naming it: refused at
// step 0 for a contact on the grid edge (exit 2), a normal solve that fails at step 0 (exit 3,
// its inputs saved beside its files), and a run that fails at step 4, after checkpoints.
// The results so kept still resume.
TEST_F(Faults, FailedOverwriteKeepsTheResultsItReplaces) {
  const fs::path ref = light(), d = dir_ / "kept", failed = d / ".fretbem-failed";
  ASSERT_EQ(run("run " + kScenario + kLight + " --stop-after 50 --out " + d.string(), dir_).code,
            0);
  const auto before = run_files(d);
  const std::string again = "run " + kScenario + kLight + " --overwrite --out " + d.string();
  Result r = run(again + " --set load.normal_force=2000", dir_);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("step 0: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("put back, its own files are in " + failed.string()), std::string::npos)
      << r.err;
  EXPECT_TRUE(run_files(d) == before);
  EXPECT_TRUE(fs::exists(failed / "timeseries.csv"));
  r = run(again + " --set solver.max_iterations=1", dir_);
  EXPECT_EQ(r.code, 3) << r.err;
  EXPECT_NE(r.err.find("its inputs are in " + (failed / "failed_solve.h5").string()),
            std::string::npos)
      << r.err;
  EXPECT_TRUE(fs::exists(failed / "failed_solve.h5"));
  EXPECT_TRUE(run_files(d) == before);
  r = run(late_failing_run(dir_) + " --overwrite --out " + d.string(), dir_);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("step 4: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(failed.string()), std::string::npos) << r.err;
  EXPECT_TRUE(run_files(d) == before);
  EXPECT_TRUE(fs::exists(failed / "checkpoint.h5"));     // it failed after its checkpoints
  EXPECT_FALSE(fs::exists(failed / "failed_solve.h5"));  // the older failed run's is gone
  EXPECT_FALSE(fs::exists(d / ".fretbem-replaced"));
  ASSERT_EQ(run("run --resume " + d.string() + " --quiet", dir_).code, 0);
  expect_same_rows(ref, d);
}

// A run with --overwrite that is stopped (--stop-after, SIGTERM) keeps its checkpoint and the
// results it replaces; resumed to the end it removes them and equals an uninterrupted run; a
// resume that fails (its checkpoint damaged) puts them back.
TEST_F(Faults, StoppedOverwriteKeepsTheResultsUntilItFinishes) {
  const fs::path ref = light(), d = dir_ / "stopped";
  ASSERT_EQ(run("run " + kScenario + kLight + " --stop-after 20 --out " + d.string(), dir_).code,
            0);
  const auto old = run_files(d);
  const std::string stopped =
      "run " + kScenario + kLight + " --overwrite --stop-after 30 --out " + d.string();
  ASSERT_EQ(run(stopped, dir_).code, 0);
  EXPECT_TRUE(run_files(d / ".fretbem-replaced") == old);
  EXPECT_EQ(rows_of(d / "timeseries.csv").size(), 31u);  // header + steps 0 to 29
  ASSERT_EQ(run("run --resume " + d.string() + " --quiet --stop-after 30", dir_).code, 0);
  EXPECT_TRUE(run_files(d / ".fretbem-replaced") == old);
  ASSERT_EQ(run("run --resume " + d.string() + " --quiet", dir_).code, 0);
  EXPECT_FALSE(fs::exists(d / ".fretbem-replaced"));
  expect_same_rows(ref, d);
  // Stopped again by SIGTERM (pending at its start: it stops after step 0), its checkpoint
  // then cut short: the resume is refused and the results put back.
  const auto finished = run_files(d);
  const int code = fretbem_test::wait_exit(fretbem_test::spawn_with_pending_signal(
      SIGTERM,
      {kBin, "run", kScenario, "--quiet", "--set", "grid.n=16", "--overwrite", "--out", d.string()},
      dir_ / "signal.out", dir_ / "signal.err"));
  ASSERT_EQ(code, 128 + SIGTERM) << slurp(dir_ / "signal.err");
  EXPECT_TRUE(run_files(d / ".fretbem-replaced") == finished);
  fs::resize_file(d / "checkpoint.h5", fs::file_size(d / "checkpoint.h5") / 2);
  const Result r = run("run --resume " + d.string() + " --quiet", dir_);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("put back"), std::string::npos) << r.err;
  EXPECT_TRUE(run_files(d) == finished);
  EXPECT_TRUE(fs::exists(d / ".fretbem-failed" / "checkpoint.h5"));
}

// A run with --overwrite on a disk that fills after its first checkpoints (a tmpfs with room
// for the old results and a little more, when root): exit 1 with one line naming the full
// file and where the failed run's files went, the old results back byte for byte.
TEST_F(Faults, FullDiskOverwriteKeepsTheResultsItReplaces) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to mount a tmpfs";
  const fs::path old = dir_ / "old", mnt = dir_ / "tmpfs", d = mnt / "r";
  ASSERT_EQ(run("run " + kScenario + kLight + " --stop-after 50 --out " + old.string(), dir_).code,
            0);
  if (!mount_room_for(old, 150, mnt)) GTEST_SKIP() << "cannot mount a tmpfs here";
  fs::copy(old, d);
  const Result r = run("run " + kScenario + kQuick + " --overwrite --out " + d.string(), dir_);
  const auto after = run_files(d);
  const bool checkpointed = fs::exists(d / ".fretbem-failed" / "checkpoint.h5");
  ::umount(mnt.c_str());
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("put back, its own files are in " + (d / ".fretbem-failed").string()),
            std::string::npos)
      << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_TRUE(after == run_files(old));
  EXPECT_TRUE(checkpointed);  // it failed after its first checkpoint
}

// `ensemble --overwrite` runs its members with --overwrite: a member that fails leaves the
// results it was to replace as they were and its own files in its .fretbem-failed.
TEST_F(Faults, EnsembleOverwriteKeepsAFailedMembersResults) {
  const fs::path out = dir_ / "e", member = out / "H0.5" / "seed_001";
  const std::string cmd =
      "ensemble " + (fs::path(FRETBEM_SOURCE_DIR) / "scenarios" / "rough_monotone.ini").string() +
      " --hurst 0.5 --seeds 1 --quiet --set grid.n=16 --set load.steps=10 --out " + out.string();
  ASSERT_EQ(run(cmd, dir_).code, 0);
  const auto before = run_files(member);
  ASSERT_TRUE(before.count("timeseries.csv"));
  const Result r = run(cmd + " --overwrite --set solver.max_iterations=1", dir_);
  EXPECT_EQ(r.code, 4) << r.err;
  // The study's own files of the member (its status, its log) are rewritten; the run's not.
  const auto without_study_files = [](std::map<std::string, std::string> files) {
    files.erase("log.txt"), files.erase("sweep_member.txt");
    return files;
  };
  EXPECT_TRUE(without_study_files(run_files(member)) == without_study_files(before));
  EXPECT_TRUE(fs::exists(member / ".fretbem-failed" / "failed_solve.h5"));
  // Run again without --overwrite, the failed member runs again and still replaces them only
  // once it finishes: failing once more, it leaves them as they were, not an emptied folder.
  const Result again = run(cmd + " --set solver.max_iterations=1", dir_);
  EXPECT_EQ(again.code, 4) << again.err;
  EXPECT_EQ(sweep_test::column(out / "members.csv", "status"), std::vector<std::string>{"failed"});
  EXPECT_TRUE(without_study_files(run_files(member)) == without_study_files(before));
  // Finishing, it replaces them: the rows of the first run, whose scenario it runs again.
  ASSERT_EQ(run(cmd, dir_).code, 0);
  EXPECT_EQ(sweep_test::column(out / "members.csv", "status"), std::vector<std::string>{"ok"});
  EXPECT_EQ(slurp(member / "timeseries.csv"), before.at("timeseries.csv"));
}

// A run with --overwrite killed (SIGKILL) while setting the old results aside, while putting
// them back, or before its first checkpoint, or after it: the next run or resume in the folder
// finds the states such a kill leaves (replaced_results.hpp) and keeps one run's files, never a
// mix; after a checkpoint the new run stays resumable and the results it replaces stay aside.
TEST_F(Faults, KilledOverwriteIsSettledByTheNextRun) {
  const fs::path ref = light(), d = dir_ / "settle";
  const std::string stopped = "run " + kScenario + kLight + " --stop-after 50 --out " + d.string();
  ASSERT_EQ(run(stopped, dir_).code, 0);
  const auto old = folder_bytes(d);
  // Killed while moving: two files already aside, the rest still in the folder.
  fs::create_directory(d / ".fretbem-replacing");
  for (const char* f : {"checkpoint.h5", "result.h5"})
    fs::rename(d / f, d / ".fretbem-replacing" / f);
  Result r = run("run " + kScenario + kLight + " --out " + d.string(), dir_);
  EXPECT_EQ(r.code, 2) << r.err;  // the old results are back, and not overwritten unasked
  EXPECT_NE(r.err.find("holds the results of another run"), std::string::npos) << r.err;
  EXPECT_TRUE(folder_bytes(d) == old);
  // Killed while putting them back after a failure: the checkpoint and the time series still in
  // the restoring folder, the rest back in place of the new run's.
  fs::create_directory(d / ".fretbem-restoring");
  for (const char* f : {"checkpoint.h5", "timeseries.csv"})
    fs::rename(d / f, d / ".fretbem-restoring" / f);
  std::ofstream(d / "timeseries.csv") << "the failed run's\n";
  r = run("run " + kScenario + kLight + " --out " + d.string(), dir_);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("holds the results of another run"), std::string::npos) << r.err;
  EXPECT_TRUE(folder_bytes(d) == old);
  // Killed during the new run's step 0: all old files aside, the new run's first files here.
  fs::create_directory(d / ".fretbem-replaced");
  for (const auto& [name, bytes] : old)
    if (name != ".fretbem.lock") fs::rename(d / name, d / ".fretbem-replaced" / name);
  std::ofstream(d / "timeseries.csv") << rows_of(ref / "timeseries.csv")[0][0] << "\n";
  std::ofstream(d / "result.h5") << "torn";
  r = run("run --resume " + d.string() + " --quiet", dir_);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("are put back"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / ".fretbem-replaced"));
  expect_same_rows(ref, d);
  // Killed after the new run's checkpoint (the state a stop leaves too): both are kept. A run
  // without --overwrite is refused; one with it discards the unfinished run and, failing,
  // puts back the finished results.
  const auto finished = run_files(d);
  const std::string replacing = "run " + kScenario + kLight + " --overwrite --out " + d.string();
  ASSERT_EQ(run(replacing + " --stop-after 3", dir_).code, 0);
  r = run("run " + kScenario + kLight + " --out " + d.string(), dir_);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_TRUE(run_files(d / ".fretbem-replaced") == finished);
  EXPECT_EQ(rows_of(d / "timeseries.csv").size(), 4u);  // header + steps 0 to 2
  r = run(replacing + " --set load.normal_force=2000", dir_);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_TRUE(run_files(d) == finished);
  EXPECT_FALSE(fs::exists(d / ".fretbem-replaced"));
  // Resumed after such a kill: the new run finishes and the results it replaced are removed.
  ASSERT_EQ(run(replacing + " --stop-after 3", dir_).code, 0);
  ASSERT_TRUE(fs::exists(d / ".fretbem-replaced"));
  ASSERT_EQ(run("run --resume " + d.string() + " --quiet", dir_).code, 0);
  EXPECT_FALSE(fs::exists(d / ".fretbem-replaced"));
  expect_same_rows(ref, d);
}

// A blank, whitespace or comment line among the finished rows of timeseries.csv is refused
// by --resume with the file and line named, before anything is written: kept by line count,
// the rows would lose one finished row per such line.
TEST_F(Faults, ResumeRefusesLinesWithoutDataAmongFinishedRows) {
  const fs::path d = dir_ / "lines", ts = d / "timeseries.csv";
  ASSERT_EQ(run("run " + kScenario + kLight + " --stop-after 100 --out " + d.string(), dir_).code,
            0);
  const std::string good = slurp(ts);
  std::string::size_type at = 0;
  for (int line = 1; line < 50; ++line) at = good.find('\n', at) + 1;  // start of line 50
  for (const std::string extra : {"\n", "  \t\n", "# a note\n"}) {
    std::ofstream(ts, std::ios::binary) << good.substr(0, at) + extra + good.substr(at);
    const auto before = folder_bytes(d);
    const Result r = run("run --resume " + d.string() + " --quiet", dir_);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find(ts.string() + ":50: "), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(folder_bytes(d) == before);
  }
  std::ofstream(ts, std::ios::binary) << good;
  ASSERT_EQ(run("run --resume " + d.string() + " --quiet", dir_).code, 0);
  expect_same_rows(light(), d);
}

// Every file a resume reads or appends must be a regular file: a FIFO would block the resume
// in open() (past a SIGTERM), a folder would fail it with a message naming no file. Both
// are refused with one line naming the file, exit 2. `timeout` only ends the blocked open of
// a binary without the check; it plays no part when the check is there.
TEST_F(Faults, ResumeRefusesRunFilesThatAreNotRegularFiles) {
  const fs::path d = dir_ / "special";
  ASSERT_EQ(run("run " + kScenario + kLight + " --stop-after 20 --out " + d.string(), dir_).code,
            0);
  fs::rename(d / "cycles.csv", dir_ / "cycles.csv");
  for (const std::string kind : {"FIFO", "folder"}) {
    if (kind == "FIFO")
      ASSERT_EQ(::mkfifo((d / "cycles.csv").c_str(), 0644), 0);
    else
      fs::create_directory(d / "cycles.csv");
    const Result r = run("run --resume " + d.string() + " --quiet", dir_, "timeout 300 ");
    EXPECT_EQ(r.code, 2) << kind << ": " << r.err;
    EXPECT_NE(r.err.find((d / "cycles.csv").string() + ": is a " + kind), std::string::npos)
        << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    fs::remove(d / "cycles.csv");
  }
  fs::rename(dir_ / "cycles.csv", d / "cycles.csv");
  EXPECT_EQ(run("run --resume " + d.string() + " --quiet", dir_).code, 0);
}

// The root folder and the home folder are never one run's folder (`--out "$OUT/"` with OUT
// unset): refused with the folder named, nothing written there.
TEST_F(Faults, RootAndHomeAreNotOutputFolders) {
  const std::string normal_only = kScenario + " --quiet --set grid.n=8 --set load.path=none";
  Result r = run("run " + normal_only + " --out /", dir_);
  const bool wrote = fs::exists("/timeseries.csv");
  for (const char* f : {"timeseries.csv", "cycles.csv", "result.h5", "checkpoint.h5", "result.xmf",
                        ".fretbem.lock"})
    if (wrote) fs::remove(fs::path("/") / f);  // undo what a binary without the check wrote
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_FALSE(wrote);
  EXPECT_EQ(r.err.rfind("fretbem: error: /: the root folder", 0), 0u) << r.err;
  const Result c = run("check " + normal_only + " --no-estimate --out /", dir_);  // as run
  EXPECT_EQ(c.code, 2) << c.err;
  EXPECT_EQ(c.err, r.err);
  const fs::path home = dir_ / "home";
  fs::create_directories(home);
  const int st = std::system(("HOME=" + home.string() + " " + kBin + " run " + normal_only +
                              " --out " + home.string() + "/ 2> " + (dir_ / "home.err").string())
                                 .c_str());
  EXPECT_EQ(WEXITSTATUS(st), 2);
  EXPECT_NE(slurp(dir_ / "home.err").find(home.string() + "/: the home folder"), std::string::npos)
      << slurp(dir_ / "home.err");
  EXPECT_TRUE(fs::is_empty(home));
}
