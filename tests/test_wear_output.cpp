// Wear-run outputs through the command line: cycles.csv (one row per simulated
// cycle, `accepted` marking the integrator's solution), wear of both bodies
// (wear.indenter_share), checkpoints, --stop-after and --resume.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "support/child_process.hpp"
#include "support/temp_dir.hpp"
#include "support/varying_normal_table.hpp"

namespace fs = std::filesystem;

namespace {

const std::string kBin = FRETBEM_BINARY;

// Partial slip on the Hertz sphere of fretting_wear.ini at n = 32 (a ~ 8 cells), Archard
// k = 2e-12 1/Pa: a few hundred cycles wear the slip annulus visibly.
std::string run_args(const fs::path& out, const std::string& integrator, double N,
                     const std::string& extra = "") {
  return "run " + (fs::path(FRETBEM_SOURCE_DIR) / "scenarios" / "fretting_wear.ini").string() +
         " --quiet --set grid.n=32 --set wear.coefficient=2e-12 --set wear.integrator=" +
         integrator + " --set wear.cycles=" + std::to_string(int(N)) + " " + extra + " --out " +
         out.string();
}

int sh(const std::string& args) {
  return std::system((kBin + " " + args + " > /dev/null 2>&1").c_str());
}

fs::path fresh_dir(const std::string& name) {
  return fretbem_test::process_temp_dir().vacant(name);
}

struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  std::vector<std::size_t> widths;  // cells per data row (a torn row has fewer)
  std::size_t col(const std::string& name) const {
    const auto it = std::find(header.begin(), header.end(), name);
    EXPECT_NE(it, header.end()) << name;
    return std::size_t(it - header.begin());
  }
  std::vector<double> column(const std::string& name) const {
    const std::size_t c = col(name);
    std::vector<double> out;
    for (const auto& r : rows) out.push_back(r.at(c));
    return out;
  }
};

Csv read_csv(const fs::path& p) {
  std::ifstream in(p);
  Csv c;
  std::string line;
  if (std::getline(in, line)) {
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) c.header.push_back(cell);
  }
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) row.push_back(std::stod(cell));
    c.widths.push_back(row.size());
    c.rows.push_back(row);
  }
  return c;
}

// A 2-D dataset of result.h5 as a flat vector (the order does not matter for the checks).
std::vector<double> h5_field(const fs::path& file, const std::string& name) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  EXPECT_GE(f, 0) << file;
  const hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  EXPECT_GE(d, 0) << name;
  const hid_t s = H5Dget_space(d);
  std::vector<double> out(std::size_t(H5Sget_simple_extent_npoints(s)));
  EXPECT_GE(H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()), 0);
  H5Sclose(s);
  H5Dclose(d);
  H5Fclose(f);
  return out;
}

// Snapshot groups /wear/snapshot_* of result.h5: N -> total worn depth.
std::map<double, std::vector<double>> h5_snapshots(const fs::path& file) {
  std::map<double, std::vector<double>> out;
  for (int k = 0;; ++k) {
    char name[64];
    std::snprintf(name, sizeof name, "/wear/snapshot_%06d", k);
    const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    const bool has = H5Lexists(f, name, H5P_DEFAULT) > 0;
    double N = 0.0;
    if (has) {
      const hid_t a = H5Aopen_by_name(f, name, "time", H5P_DEFAULT, H5P_DEFAULT);
      H5Aread(a, H5T_NATIVE_DOUBLE, &N);
      H5Aclose(a);
    }
    H5Fclose(f);
    if (!has) return out;
    out[N] = h5_field(file, std::string(name) + "/worn_depth");
  }
}

double max_abs(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

double max_diff(const std::vector<double>& a, const std::vector<double>& b) {
  EXPECT_EQ(a.size(), b.size());
  double m = 0.0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}

double sum(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return s;
}

constexpr double kCellArea = (2.8e-4 / 32) * (2.8e-4 / 32);

}  // namespace

// Cycle mode: one row per simulated cycle, N = 0..N_end, every row accepted; no wear.csv.
TEST(WearCyclesCsv, CycleModeOneRowPerCycle) {
  const fs::path d = fresh_dir("cycle");
  ASSERT_EQ(sh(run_args(d, "cycle", 12)), 0);
  const Csv c = read_csv(d / "cycles.csv");
  const std::vector<std::string> head{
      "N",          "energy_per_cycle", "wear_volume", "max_worn_depth", "contact_radius",
      "stick_area", "peak_pressure",    "delta",       "max_slip",       "simulated_cycles",
      "accepted"};
  ASSERT_GE(c.header.size(), head.size());
  EXPECT_TRUE(std::equal(head.begin(), head.end(), c.header.begin()));
  EXPECT_FALSE(fs::exists(d / "wear.csv"));
  ASSERT_EQ(c.rows.size(), 13u);
  for (std::size_t k = 0; k < c.rows.size(); ++k) {
    EXPECT_EQ(c.rows[k][c.col("N")], double(k));
    EXPECT_EQ(c.rows[k][c.col("accepted")], 1.0);
    EXPECT_EQ(c.rows[k][c.col("simulated_cycles")], double(k + 1));
  }
  // The last row observes the final surface: its volume is that of the final worn depth.
  const auto W = h5_field(d / "result.h5", "/wear/final_worn_depth");
  EXPECT_NEAR(c.rows.back()[c.col("wear_volume")] / (sum(W) * kCellArea), 1.0, 1e-12);
  EXPECT_GT(sum(W), 0.0);
  fs::remove_all(d);
}

// ERK: every wear-map evaluation is a row; the accepted ones are the integrator's solution:
// N strictly increasing from 0 to N_end, the worn volume never decreasing (dW/dN >= 0 and
// Heun–Euler's update W + h (k1 + k2)/2 has positive weights), and at every snapshot N an
// accepted row ran on exactly the snapshot's worn depth (volume to round-off).
TEST(WearCyclesCsv, ErkAcceptedRowsAreTheSolution) {
  const fs::path d = fresh_dir("erk");
  ASSERT_EQ(sh(run_args(d, "erk", 300)), 0);
  const Csv c = read_csv(d / "cycles.csv");
  std::vector<double> N, V;
  int trial = 0;
  for (const auto& r : c.rows) {
    if (r[c.col("accepted")] == 0.0) {
      ++trial;
      continue;
    }
    N.push_back(r[c.col("N")]), V.push_back(r[c.col("wear_volume")]);
  }
  ASSERT_GE(N.size(), 3u);
  EXPECT_GT(trial, 0);  // the second Heun–Euler stage is never a solution point
  EXPECT_EQ(N.front(), 0.0);
  EXPECT_EQ(N.back(), 300.0);
  for (std::size_t k = 1; k < N.size(); ++k) {
    EXPECT_GT(N[k], N[k - 1]);
    EXPECT_GE(V[k], V[k - 1]);
  }
  const auto snaps = h5_snapshots(d / "result.h5");
  ASSERT_GE(snaps.size(), 5u);  // 0, 1, 2, 5, ..., 300
  for (const auto& [n, W] : snaps) {
    const auto it = std::find(N.begin(), N.end(), n);
    ASSERT_NE(it, N.end()) << "no accepted row at snapshot N = " << n;
    const double v = sum(W) * kCellArea, row = V[std::size_t(it - N.begin())];
    EXPECT_NEAR(row, v, 1e-12 * std::max(v, 1e-30)) << "N = " << n;
  }
  fs::remove_all(d);
}

// --stop-after 5 in cycle mode stops after five simulated cycles with complete outputs; the
// resumed run ends on the uninterrupted run's worn depth (the same arithmetic from the same
// saved state: round-off only).
TEST(WearResume, CycleModeStopAndResume) {
  const fs::path full = fresh_dir("cyc_full"), part = fresh_dir("cyc_part");
  ASSERT_EQ(sh(run_args(full, "cycle", 12)), 0);
  ASSERT_EQ(sh(run_args(part, "cycle", 12, "--stop-after 5")), 0);
  const Csv stopped = read_csv(part / "cycles.csv");
  ASSERT_EQ(stopped.rows.size(), 5u);  // N = 0..4
  EXPECT_EQ(stopped.rows.back()[stopped.col("N")], 4.0);
  EXPECT_TRUE(fs::exists(part / "checkpoint.h5"));
  ASSERT_EQ(sh("run --quiet --resume " + part.string()), 0);
  const auto Wf = h5_field(full / "result.h5", "/wear/final_worn_depth");
  const auto Wp = h5_field(part / "result.h5", "/wear/final_worn_depth");
  ASSERT_GT(max_abs(Wf), 0.0);
  EXPECT_LE(max_diff(Wf, Wp), 1e-9 * max_abs(Wf));
  const Csv a = read_csv(full / "cycles.csv"), b = read_csv(part / "cycles.csv");
  EXPECT_EQ(a.column("N"), b.column("N"));  // continued, no row lost or repeated
  EXPECT_EQ(a.column("simulated_cycles"), b.column("simulated_cycles"));
  EXPECT_EQ(read_csv(full / "timeseries.csv").rows.size(),
            read_csv(part / "timeseries.csv").rows.size());
  fs::remove_all(full);
  fs::remove_all(part);
}

// A varying normal load leaves nodes on their bound without slipping (NodeState::stuck_at_bound)
// at the end of a cycle; the checkpoint holds them and the resumed run is the uninterrupted one.
TEST(WearResume, CycleModeResumesWithNodesStuckAtTheirBound) {
  const fs::path full = fresh_dir("sab_full"), part = fresh_dir("sab_part");
  const fs::path table = fresh_dir("sab_table.csv");
  std::ofstream(table) << "time,Fz,Fx\n0,10,0\n0.125,13,1.41421\n0.25,10,2\n0.375,7,1.41421\n"
                          "0.5,10,2.4e-16\n0.625,13,-1.41421\n0.75,10,-2\n0.875,7,-1.41421\n"
                          "1,10,-4.9e-16\n";
  const std::string args =
      "run " + (fs::path(FRETBEM_SOURCE_DIR) / "scenarios" / "varying_normal.ini").string() +
      " --quiet --set load.table=" + table.string() +
      " --set grid.n=32 --set wear.law=archard --set wear.coefficient=5e-14 --set wear.cycles=5"
      " --set wear.integrator=cycle --out ";
  ASSERT_EQ(sh(args + full.string()), 0);
  ASSERT_EQ(sh(args + part.string() + " --stop-after 1"), 0);
  ASSERT_EQ(sh("run --quiet --resume " + part.string()), 0);
  const auto Wf = h5_field(full / "result.h5", "/wear/final_worn_depth");
  ASSERT_GT(max_abs(Wf), 0.0);
  EXPECT_EQ(Wf, h5_field(part / "result.h5", "/wear/final_worn_depth"));
  const Csv a = read_csv(full / "cycles.csv"), b = read_csv(part / "cycles.csv");
  EXPECT_EQ(a.column("N"), b.column("N"));
  EXPECT_EQ(a.column("energy_per_cycle"), b.column("energy_per_cycle"));
  EXPECT_EQ(a.column("wear_volume"), b.column("wear_volume"));
  fs::remove_all(full);
  fs::remove_all(part);
  fs::remove(table);
}

// ERK: stop after 3 accepted steps, resume with a fresh integrator at (N, W) and the saved
// step. ERK restarts at every accepted state anyway, and the checkpoint holds the pressure the
// next wear-map evaluation starts its normal solve from, so the resumed evaluations are the
// uninterrupted ones: the same worn depth to round-off. Any run resumed with a fresh
// integrator stays within rtol times the final depth.
TEST(WearResume, ErkStopAndResumeWithinTolerance) {
  const double rtol = 1e-3;
  const fs::path full = fresh_dir("erk_full"), part = fresh_dir("erk_part");
  ASSERT_EQ(sh(run_args(full, "erk", 300)), 0);
  ASSERT_EQ(sh(run_args(part, "erk", 300, "--stop-after 3")), 0);
  ASSERT_EQ(sh("run --quiet --resume " + part.string()), 0);
  const auto Wf = h5_field(full / "result.h5", "/wear/final_worn_depth");
  const auto Wp = h5_field(part / "result.h5", "/wear/final_worn_depth");
  ASSERT_GT(max_abs(Wf), 0.0);
  const double rel = max_diff(Wf, Wp) / max_abs(Wf);
  std::printf("[ erk resume ] max |W_resumed - W| / max W = %.3g\n", rel);
  EXPECT_LE(rel, rtol);
  EXPECT_LE(rel, 1e-12);
  const Csv b = read_csv(part / "cycles.csv");
  double prev = -1.0;
  for (const auto& r : b.rows) {
    if (r[b.col("accepted")] != 1.0) continue;
    EXPECT_GT(r[b.col("N")], prev);
    prev = r[b.col("N")];
  }
  EXPECT_EQ(prev, 300.0);
  // The resumed run's rows are the uninterrupted run's, the first row after the resume (the
  // state of the checkpoint) accepted as it is there.
  const Csv a = read_csv(full / "cycles.csv");
  ASSERT_EQ(a.rows.size(), b.rows.size());
  for (std::size_t k = 0; k < a.rows.size(); ++k) {
    EXPECT_EQ(a.rows[k][a.col("accepted")], b.rows[k][b.col("accepted")]) << "row " << k;
    EXPECT_NEAR(a.rows[k][a.col("N")], b.rows[k][b.col("N")], 1e-9 * 300) << "row " << k;
  }
  fs::remove_all(full);
  fs::remove_all(part);
}

namespace {

// Runs `ini` stopped after each of `stops` steps (--stop-after) into a fresh folder
// `name`+stop, resumes it to the end and hands the folder to `check`.
void for_each_resumed_stop(const fs::path& ini, const std::string& name,
                           std::initializer_list<int> stops,
                           const std::function<void(const fs::path&, int)>& check) {
  for (int stop : stops) {
    const fs::path part = fresh_dir(name + std::to_string(stop));
    ASSERT_EQ(sh("run " + ini.string() + " --quiet --out " + part.string() + " --stop-after " +
                 std::to_string(stop)),
              0);
    ASSERT_EQ(sh("run --quiet --resume " + part.string()), 0);
    check(part, stop);
    fs::remove_all(part);
  }
}

}  // namespace

// A stop right after an explicit step whose last stage ran on the new state: that state's
// accepted row is already in cycles.csv when the checkpoint is written, and the resumed run's
// first evaluation there is a repeat (accepted = 0), as in the uninterrupted run. A flat in
// full stick under static/kinetic friction and a varying normal load (no wear: every state is
// the unworn surface), stopped after one and after two steps; and after the fifth and sixth,
// where the cost guard simulates stretches of cycles one by one, doubling a stretch while the
// integrator stays unprofitable: the checkpoint carries the next stretch, so the resumed run
// takes the uninterrupted one's stretches (N and flags equal).
TEST(WearResume, ErkResumeKeepsTheAcceptedFlagsOfAStateThatHasItsRow) {
  const fs::path table = fresh_dir("flag_table.csv");
  std::ofstream(table) << "time,Fz,Fx\n0,7.222,0\n0.125,9.389,1.912\n0.25,7.222,2.080\n"
                          "0.375,5.055,1.030\n0.5,7.222,0\n0.625,9.389,-1.912\n"
                          "0.75,7.222,-2.080\n0.875,5.055,-1.030\n1,7.222,0\n";
  const fs::path ini = fresh_dir("flag.ini");
  std::ofstream(ini)
      << "[material]\nE = 7e10\nnu = 0.49\nmu = 0.8\n[grid]\nn = 16\nlength = 2.8e-4\n"
         "[surface]\ntype = flat\n[friction]\nlaw = static_kinetic\nmu_kinetic = 0.48\n"
         "[load]\npath = table\ntable = "
      << table.string()
      << "\n[wear]\nlaw = energy\nintegrator = arkode\ncycles = 40\ncoefficient = 2.1e-9\n";
  const fs::path full = fresh_dir("flag_full");
  ASSERT_EQ(sh("run " + ini.string() + " --quiet --out " + full.string()), 0);
  const Csv a = read_csv(full / "cycles.csv");
  for_each_resumed_stop(ini, "flag_part", {1, 2, 5, 6}, [&](const fs::path& part, int stop) {
    const Csv b = read_csv(part / "cycles.csv");
    EXPECT_EQ(a.column("accepted"), b.column("accepted")) << "stopped after " << stop;
    EXPECT_EQ(a.column("N"), b.column("N")) << "stopped after " << stop;
  });
  fs::remove_all(full);
  fs::remove(ini);
  fs::remove(table);
}

// A stretch of cycles runs on through the snapshots it reaches (rough surface, F_z +-30 %,
// Cerruti, dirk with Krylov Newton, n = 16, N = 100: one TR-BDF2 step to N = 1, then cycles
// one by one in pieces ending at N = 2, 5, 10, ...). The checkpoint holds the stretch's rest
// and the failed step's cost (`wear_stretch_left`), so a run stopped after the step, or after
// the piece to N = 2 or 5, takes the uninterrupted run's pieces: every cycles.csv cell and the
// final worn depth equal bit for bit (each piece starts from the steady cycle of the worn
// depth, the same in both runs).
TEST(WearResume, StretchAcrossSnapshotsResumesAsUninterrupted) {
  const fs::path table = fresh_dir("stretch_table.csv");
  std::ofstream(table) << fretbem_test::kTwelveRowVaryingTable;
  const fs::path ini = fresh_dir("stretch.ini");
  std::ofstream(ini) << "[material]\nE = 5e9\nnu = 0.25\nmu = 0.5\n[grid]\nn = 16\n"
                        "length = 2.8e-4\n[surface]\ntype = rough\nmethod = midpoint\n"
                        "hurst = 0.3\nseed = 224\nrms_slope = 0.02\n[load]\npath = table\n"
                        "control = force\ntable = "
                     << table.string()
                     << "\n[solver]\ntolerance = 1e-8\ncoupling = cerruti\n[wear]\n"
                        "law = archard\ncoefficient = 8.0357e-11\nrtol = 1e-3\n"
                        "newton = krylov\nintegrator = dirk\ncycles = 100\n";
  const fs::path full = fresh_dir("stretch_full");
  ASSERT_EQ(sh("run " + ini.string() + " --quiet --out " + full.string()), 0);
  const Csv a = read_csv(full / "cycles.csv");
  const auto Wf = h5_field(full / "result.h5", "/wear/final_worn_depth");
  for_each_resumed_stop(ini, "stretch_part", {1, 2, 3}, [&](const fs::path& part, int stop) {
    const Csv b = read_csv(part / "cycles.csv");
    EXPECT_EQ(a.rows, b.rows) << "stopped after " << stop;
    EXPECT_EQ(Wf, h5_field(part / "result.h5", "/wear/final_worn_depth"))
        << "stopped after " << stop;
  });
  fs::remove_all(full);
  fs::remove(ini);
  fs::remove(table);
}

// The explicit integrator's error test weighs W against rtol |W| + atol, atol = rtol times the
// unworn indentation, which a probe loading solves to solver.tolerance. A resumed run reads
// atol from the checkpoint: probing again from the last evaluation's pressure lands within that
// tolerance, not on the same double, and moves the step chosen after an error-test failure
// (N 6.377123523320289 -> 6.377123523320507). A periodic rough surface (n = 24, Archard) whose
// run rejects a step after the stop; stopped after one and two steps, every cycles.csv cell
// and the final worn depth equal the uninterrupted run's bit for bit.
TEST(WearResume, ErkResumeKeepsTheAbsoluteToleranceOfTheFirstRun) {
  const fs::path ini = fresh_dir("atol.ini");
  std::ofstream(ini) << "[material]\nE = 5e9\nnu = 0\nmu = 0.5\n[grid]\nn = 24\n"
                        "length = 2.8e-4\nperiodic = true\n[surface]\ntype = rough\n"
                        "method = midpoint\nhurst = 0.7\nseed = 533\nrms_height = 2.8e-7\n"
                        "[load]\npath = sine\nnormal_force = 2.352\namplitude = 0.9\n"
                        "steps_per_cycle = 12\n[wear]\nlaw = archard\nintegrator = erk\n"
                        "cycles = 200\ncoefficient = 5e-10\nrtol = 1e-3\n";
  const fs::path full = fresh_dir("atol_full");
  ASSERT_EQ(sh("run " + ini.string() + " --quiet --out " + full.string()), 0);
  const Csv a = read_csv(full / "cycles.csv");
  const auto N = a.column("N"), accepted = a.column("accepted");
  bool retried = false;  // a trial rejected, the step retried shorter from the same state
  for (std::size_t k = 1; k < N.size(); ++k) retried |= accepted[k - 1] == 0.0 && N[k] < N[k - 1];
  ASSERT_TRUE(retried);
  const auto Wf = h5_field(full / "result.h5", "/wear/final_worn_depth");
  for_each_resumed_stop(ini, "atol_part", {1, 2}, [&](const fs::path& part, int stop) {
    const Csv b = read_csv(part / "cycles.csv");
    EXPECT_EQ(a.header, b.header);
    EXPECT_EQ(a.rows, b.rows) << "stopped after " << stop;
    EXPECT_EQ(Wf, h5_field(part / "result.h5", "/wear/final_worn_depth"))
        << "stopped after " << stop;
  });
  fs::remove_all(full);
  fs::remove(ini);
}

namespace {

// Starts the cycle-mode run of run_args(out, "cycle", N) in the background, sends it `sig`
// once its cycles.csv holds `rows` rows, and returns its wait status.
int signal_after_rows(const fs::path& out, int N, std::size_t rows, int sig) {
  const pid_t pid = fork();
  if (pid == 0) {
    const std::string cmd = "exec " + kBin + " " + run_args(out, "cycle", N) + " > /dev/null";
    execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  if (!fretbem_test::wait_until(
          pid, [&] { return read_csv(out / "cycles.csv").rows.size() >= rows; }, &status))
    return status;  // ended by itself: the caller's checks say so
  kill(pid, sig);
  waitpid(pid, &status, 0);
  return status;
}

}  // namespace

// A cycle-mode wear run killed with SIGKILL keeps complete rows and resumes to the
// uninterrupted run's worn depth (round-off), every cycle N listed once.
TEST(WearResume, KilledRunResumes) {
  const int N = 120;
  const fs::path full = fresh_dir("kill_full"), part = fresh_dir("kill_part");
  ASSERT_EQ(sh(run_args(full, "cycle", N)), 0);
  signal_after_rows(part, N, 20, SIGKILL);
  const Csv killed = read_csv(part / "cycles.csv");
  std::printf("[ kill ] %zu of %d cycles.csv rows on disk when killed\n", killed.rows.size(),
              N + 1);
  ASSERT_GE(killed.rows.size(), 2u);
  for (std::size_t w : killed.widths) EXPECT_EQ(w, killed.header.size());
  ASSERT_EQ(sh("run --quiet --resume " + part.string()), 0);
  const auto Wf = h5_field(full / "result.h5", "/wear/final_worn_depth");
  const auto Wp = h5_field(part / "result.h5", "/wear/final_worn_depth");
  EXPECT_LE(max_diff(Wf, Wp), 1e-9 * max_abs(Wf));
  const auto Nc = read_csv(part / "cycles.csv").column("N");
  ASSERT_EQ(Nc.size(), std::size_t(N + 1));
  for (int k = 0; k <= N; ++k) EXPECT_EQ(Nc[std::size_t(k)], double(k));
  fs::remove_all(full);
  fs::remove_all(part);
}

// SIGINT (Ctrl-C) ends a cycle-mode wear run after the cycle in progress, checkpointed:
// exit 130, and --resume reaches the uninterrupted run's worn depth (round-off).
TEST(WearResume, InterruptedRunResumes) {
  const int N = 120;
  const fs::path full = fresh_dir("int_full"), part = fresh_dir("int_part");
  ASSERT_EQ(sh(run_args(full, "cycle", N)), 0);
  const int status = signal_after_rows(part, N, 20, SIGINT);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  const std::size_t rows = read_csv(part / "cycles.csv").rows.size();
  EXPECT_LT(rows, std::size_t(N + 1));
  ASSERT_EQ(sh("run --quiet --resume " + part.string()), 0);
  const auto Wf = h5_field(full / "result.h5", "/wear/final_worn_depth");
  const auto Wp = h5_field(part / "result.h5", "/wear/final_worn_depth");
  EXPECT_LE(max_diff(Wf, Wp), 1e-9 * max_abs(Wf));
  EXPECT_EQ(read_csv(part / "cycles.csv").rows.size(), std::size_t(N + 1));
  fs::remove_all(full);
  fs::remove_all(part);
}

// A stop requested before a wear run began (SIGTERM pending at its start) ends it after its
// first wear step, checkpointed (exit 143), and --resume reaches the uninterrupted run's worn
// depth (round-off): cycle by cycle and with the explicit integrator, which restarts at every
// accepted step anyway.
TEST(WearResume, StopRequestedAtTheStartResumes) {
  for (const std::string integrator : {"cycle", "erk"}) {
    SCOPED_TRACE(integrator);
    const int N = 20;
    const fs::path full = fresh_dir("pending_full"), part = fresh_dir("pending_part");
    ASSERT_EQ(sh(run_args(full, integrator, N)), 0);
    std::vector<std::string> args{kBin};
    std::istringstream words(run_args(part, integrator, N));
    for (std::string w; words >> w;) args.push_back(w);
    const int code = fretbem_test::wait_exit(fretbem_test::spawn_with_pending_signal(
        SIGTERM, args, part.string() + ".out", part.string() + ".err"));
    std::ifstream err(part.string() + ".err");
    const std::string text((std::istreambuf_iterator<char>(err)), {});
    EXPECT_EQ(code, 143) << text;
    EXPECT_NE(text.find("stopped by SIGTERM after N = 1 of 20 cycles"), std::string::npos) << text;
    ASSERT_EQ(sh("run --quiet --resume " + part.string()), 0);
    const auto Wf = h5_field(full / "result.h5", "/wear/final_worn_depth");
    const auto Wp = h5_field(part / "result.h5", "/wear/final_worn_depth");
    EXPECT_LE(max_diff(Wf, Wp), 1e-9 * max_abs(Wf));
    EXPECT_EQ(read_csv(part / "cycles.csv").rows.size(), read_csv(full / "cycles.csv").rows.size());
    fs::remove_all(full);
    fs::remove_all(part);
  }
}

// Both bodies wear, half each: the contact sees only the gap, i.e. the sum of the worn
// depths, so pressure, indentation (against the unworn datums) and the whole tangential
// history are those of the indenter-only run (identical arithmetic: round-off at most);
// each body carries its share of the worn depth and the volumes add up.
TEST(WearBothBodies, HalfShareSameContactHistory) {
  const fs::path one = fresh_dir("share1"), half = fresh_dir("share05");
  ASSERT_EQ(sh(run_args(one, "cycle", 10)), 0);
  ASSERT_EQ(sh(run_args(half, "cycle", 10, "--set wear.indenter_share=0.5")), 0);
  const Csv a = read_csv(one / "cycles.csv"), b = read_csv(half / "cycles.csv");
  for (const char* col : {"energy_per_cycle", "wear_volume", "contact_radius", "stick_area",
                          "peak_pressure", "delta"}) {
    const auto x = a.column(col), y = b.column(col);
    EXPECT_LE(max_diff(x, y), 1e-12 * max_abs(x)) << col;
  }
  const Csv ta = read_csv(one / "timeseries.csv"), tb = read_csv(half / "timeseries.csv");
  for (const char* col : {"Fz", "delta", "Fx", "Ux", "contact_area", "stick_area", "dissipation"}) {
    const auto x = ta.column(col), y = tb.column(col);
    EXPECT_LE(max_diff(x, y), 1e-12 * max_abs(x)) << col;
  }
  const auto V = b.column("wear_volume"), Vi = b.column("wear_volume_indenter"),
             Vh = b.column("wear_volume_half_space");
  for (std::size_t k = 0; k < V.size(); ++k) {
    EXPECT_NEAR(Vi[k], 0.5 * V[k], 1e-15 * V[k]);
    EXPECT_NEAR(Vi[k] + Vh[k], V[k], 1e-15 * V[k]);
  }
  const fs::path h5 = half / "result.h5";
  const auto W = h5_field(h5, "/wear/final_worn_depth"),
             Wi = h5_field(h5, "/wear/final_worn_depth_indenter"),
             Wh = h5_field(h5, "/wear/final_worn_depth_half_space");
  const auto z0 = h5_field(h5, "/surface/initial"), zi = h5_field(h5, "/surface/final"),
             zh = h5_field(h5, "/surface/final_half_space");
  ASSERT_GT(max_abs(W), 0.0);
  EXPECT_EQ(max_diff(W, h5_field(one / "result.h5", "/wear/final_worn_depth")), 0.0);
  const double tol = 1e-15 * max_abs(W);
  for (std::size_t k = 0; k < W.size(); ++k) {
    EXPECT_NEAR(Wi[k], 0.5 * W[k], tol);
    EXPECT_NEAR(Wh[k], 0.5 * W[k], tol);
    EXPECT_NEAR(Wi[k] + Wh[k], W[k], tol);
    EXPECT_NEAR(z0[k] - zi[k], Wi[k], 1e-15 * max_abs(z0));  // indenter height lost W_i
    EXPECT_NEAR(zh[k], -Wh[k], tol);                         // half-space surface sank W_h
  }
  fs::remove_all(one);
  fs::remove_all(half);
}

TEST(WearBothBodies, ShareOutsideUnitIntervalIsOneLineError) {
  const fs::path d = fresh_dir("badshare");
  const std::string err =
      (d.parent_path() / ("fretbem_badshare_err_" + std::to_string(getpid()))).string();
  const int s = std::system((kBin + " " + run_args(d, "cycle", 2, "--set wear.indenter_share=1.5") +
                             " > /dev/null 2> " + err)
                                .c_str());
  EXPECT_NE(s, 0);
  std::ifstream in(err);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string msg = ss.str();
  EXPECT_EQ(std::count(msg.begin(), msg.end(), '\n'), 1) << msg;
  EXPECT_NE(msg.find("wear.indenter_share"), std::string::npos) << msg;
  fs::remove(err);
  fs::remove_all(d);
}

namespace {

// The /fields/step_* groups of result.h5: step -> time attribute.
std::map<long, double> h5_field_steps(const fs::path& file) {
  std::map<long, double> out;
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  EXPECT_GE(f, 0) << file;
  if (H5Lexists(f, "/fields", H5P_DEFAULT) <= 0) return H5Fclose(f), out;
  const hid_t g = H5Gopen2(f, "/fields", H5P_DEFAULT);
  H5G_info_t info;
  H5Gget_info(g, &info);
  for (hsize_t k = 0; k < info.nlinks; ++k) {
    char name[64];
    H5Lget_name_by_idx(g, ".", H5_INDEX_NAME, H5_ITER_INC, k, name, sizeof name, H5P_DEFAULT);
    long step = 0;
    double time = 0.0;
    const hid_t s = H5Aopen_by_name(g, name, "step", H5P_DEFAULT, H5P_DEFAULT);
    const hid_t t = H5Aopen_by_name(g, name, "time", H5P_DEFAULT, H5P_DEFAULT);
    EXPECT_GE(H5Aread(s, H5T_NATIVE_LONG, &step), 0) << name;
    EXPECT_GE(H5Aread(t, H5T_NATIVE_DOUBLE, &time), 0) << name;
    H5Aclose(s);
    H5Aclose(t);
    out[step] = time;
  }
  H5Gclose(g);
  H5Fclose(f);
  return out;
}

std::string field_group(long step) {
  char name[64];
  std::snprintf(name, sizeof name, "/fields/step_%06ld", step);
  return name;
}

const std::string kFieldArgs = "--set output.fields=pressure,wear,state,traction_x";

herr_t add_link(hid_t, const char* name, const H5L_info_t*, void* names) {
  static_cast<std::vector<std::string>*>(names)->push_back(name);
  return 0;
}

// Every group and dataset of an HDF5 file, by path, in name order.
std::vector<std::string> h5_paths(const fs::path& file) {
  std::vector<std::string> names;
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  EXPECT_GE(f, 0) << file;
  H5Lvisit(f, H5_INDEX_NAME, H5_ITER_INC, add_link, &names);
  H5Fclose(f);
  return names;
}

}  // namespace

// Cycle mode saves the fields of the states a user can place: the normal loading (row 0) and
// the end of each snapshot's cycle (N = 0, 1, 2, 5, 10 and the last, 12: the wear snapshots'
// sequence), which ends at time N + 1; not the turning points of every simulated cycle. A
// snapshot's pressure is that state's pressure.
TEST(WearFields, CycleModeSavesFirstSnapshotsAndLast) {
  const fs::path d = fresh_dir("fields_cycle");
  ASSERT_EQ(sh(run_args(d, "cycle", 12, kFieldArgs)), 0);
  const Csv ts = read_csv(d / "timeseries.csv");
  const auto time = ts.column("time");
  std::map<long, double> expected{{0, 0.0}};
  for (double N : {0.0, 1.0, 2.0, 5.0, 10.0, 12.0}) {
    const auto it = std::find(time.begin(), time.end(), N + 1.0);
    ASSERT_NE(it, time.end()) << "no row ends cycle N = " << N;
    expected[long(it - time.begin())] = N + 1.0;
  }
  EXPECT_EQ(h5_field_steps(d / "result.h5"), expected);
  const fs::path h5 = d / "result.h5";
  const long last = long(time.size()) - 1;
  EXPECT_EQ(h5_field(h5, field_group(last) + "/pressure"),
            h5_field(h5, "/wear/snapshot_000005/pressure"));
  EXPECT_EQ(h5_field(h5, field_group(last) + "/wear").size(), std::size_t(32 * 32));
  fs::remove_all(d);
}

// ODE modes: the normal loading, the end of the first steady cycle (the N = 0 snapshot) and
// the end of the final observation cycle; the snapshots between them solve the normal load
// alone (their pressure and worn depth are in /wear).
TEST(WearFields, OdeModeSavesFirstFirstCycleAndLast) {
  const fs::path d = fresh_dir("fields_erk");
  ASSERT_EQ(sh(run_args(d, "erk", 300, kFieldArgs)), 0);
  const auto saved = h5_field_steps(d / "result.h5");
  const long last = long(read_csv(d / "timeseries.csv").rows.size()) - 1;
  ASSERT_EQ(saved.size(), 3u);
  EXPECT_EQ(saved.begin()->first, 0);
  EXPECT_EQ(saved.rbegin()->first, last);
  const fs::path h5 = d / "result.h5";
  const long first_cycle = std::next(saved.begin())->first;
  EXPECT_EQ(h5_field(h5, field_group(first_cycle) + "/pressure"),
            h5_field(h5, "/wear/snapshot_000000/pressure"));
  fs::remove_all(d);
}

// A wear run with fields stopped and resumed saves the uninterrupted run's fields (cycle mode:
// the same arithmetic, round-off only).
TEST(WearFields, ResumedRunSavesTheUninterruptedFields) {
  const fs::path full = fresh_dir("fields_full"), part = fresh_dir("fields_part");
  ASSERT_EQ(sh(run_args(full, "cycle", 12, kFieldArgs)), 0);
  ASSERT_EQ(sh(run_args(part, "cycle", 12, kFieldArgs + " --stop-after 5")), 0);
  ASSERT_EQ(sh("run --quiet --resume " + part.string()), 0);
  const auto a = h5_field_steps(full / "result.h5"), b = h5_field_steps(part / "result.h5");
  EXPECT_EQ(a, b);
  for (const auto& [step, t] : a)
    for (const char* f : {"pressure", "wear", "state", "traction_x"}) {
      const auto x = h5_field(full / "result.h5", field_group(step) + "/" + f);
      const auto y = h5_field(part / "result.h5", field_group(step) + "/" + f);
      EXPECT_LE(max_diff(x, y), 1e-9 * std::max(max_abs(x), 1e-300)) << step << " " << f;
    }
  fs::remove_all(full);
  fs::remove_all(part);
}

// An ODE (erk) wear run saving fields every third row, stopped after three accepted steps and
// resumed, has every group and dataset of the uninterrupted run's result.h5.
TEST(WearFields, ResumedErkRunKeepsEveryFieldGroup) {
  const fs::path full = fresh_dir("erk_fields_full"), part = fresh_dir("erk_fields_part");
  const std::string fields = kFieldArgs + " --set output.fields_every=3";
  ASSERT_EQ(sh(run_args(full, "erk", 300, fields)), 0);
  ASSERT_EQ(sh(run_args(part, "erk", 300, fields + " --stop-after 3")), 0);
  ASSERT_EQ(sh("run --quiet --resume " + part.string()), 0);
  const auto a = h5_paths(full / "result.h5");
  ASSERT_GT(std::count_if(a.begin(), a.end(),
                          [](const std::string& p) { return p.starts_with("fields/step_"); }),
            1);
  EXPECT_EQ(a, h5_paths(part / "result.h5"));
  fs::remove_all(full);
  fs::remove_all(part);
}
