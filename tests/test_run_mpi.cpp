// `fretbem run` under mpirun -n K (built only with FRETBEM_MPI): one grid distributed over the
// ranks writes the files of the serial run. Every timeseries.csv and cycles.csv column and every
// numeric dataset of result.h5 of a Mindlin cycle and a rough fretting cycle on two ranks and
// on three (uneven slabs) equal the serial run's to 1e-10 of the column's (dataset's) largest
// magnitude. The ranks change the order of the sums, so the two runs' iterates part by
// round-off and each stops within the solver tolerance of the exact increment: both are solved
// to 1e-12 (at the scenarios' 1e-8 the dissipation parts by 1.2e-10, the stopping rule's
// share), which makes the 1e-10 a statement about the distribution. The solver's cost and
// accuracy columns are the exception: the iteration counts and residuals are where each run's
// stopping test passed (the residuals are checked below the tolerance on both sides), and the
// convolution count differs by design (no sparse direct sums on a distributed grid,
// docs/mpi-grid.md). A run stopped and resumed on the ranks equals the uninterrupted serial
// run to the same bound, also when resumed on another number of ranks or serially (the
// checkpoint holds the whole grid). Refusals are one line with one exit code.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <map>

#include "support/child_process.hpp"
#include "support/csv_text.hpp"
#include "support/mpi_launch.hpp"
#include "support/varying_normal_table.hpp"
#include "sweep_test_util.hpp"

using namespace sweep_test;

namespace {

constexpr double kRelative = 1e-10;
double relative_difference(const std::vector<double>& a, const std::vector<double>& b);
constexpr double kSolverTolerance = 1e-12;
// k_x of a resumed run: the stiffness CG's warm start is not in the checkpoint
// (docs/reliability.md), and two CG solves stopped at relative residual kSolverTolerance from
// different starts part by up to the condition number times it (measured 1.1e-10 here, 11x the
// residual in the serial fault tests): 1e3 times the residual.
constexpr double kResumedKx = 1e3 * kSolverTolerance;
// k_x on another layout where every row solves it (tables): the stiffness solve's tolerance is
// floored at 1e-9 whatever solver.tolerance (history/model.cpp), and its contract holds each
// k_x within that tolerance of a tight solve, so two layouts may part by twice the floor (the
// energy stop aims at 0.1 of it: measured 1.4e-10 on the 12-row cubic table below).
constexpr double kLayoutKx = 2 * 1e-9;
// Saved fields of a table run in the default sub-steps on another layout: each tangential solve
// stops at relative residual kSolverTolerance, which leaves its traction within the condition
// number (about 1e2, above) times that of the exact one; two layouts' round-off parts them by
// that, carried on in the nodes' memory over four times the solves: 1e3 times the residual, as
// for k_x of resumed runs (measured 1.8e-10 of the largest traction on the 20-row cubic table
// below in 4 sub-steps a row, 1e-10 in one).
constexpr double kSubstepFields = 1e3 * kSolverTolerance;

// The solver's cost and accuracy columns (see the file's comment).
bool solver_cost(const std::string& column) {
  const auto ends = [&column](const std::string& tail) {
    return column.size() >= tail.size() &&
           column.compare(column.size() - tail.size(), tail.size(), tail) == 0;
  };
  return column == "convolutions" || ends("_iterations") || ends("_residual");
}

bool residual(const std::string& column) {
  return column.size() > 9 && column.compare(column.size() - 9, 9, "_residual") == 0;
}

void expect_converged(const std::vector<double>& v, const std::string& what) {
  for (double r : v)
    if (!std::isnan(r)) {
      EXPECT_LE(r, kSolverTolerance) << what;
    }
}

// Compares one column or dataset: the solver's cost columns by their bound, the rest to
// kRelative.
void expect_same_values(const std::string& name, const std::vector<double>& serial,
                        const std::vector<double>& mpi, const std::string& where,
                        double kx_bound = kRelative) {
  if (residual(name)) {
    expect_converged(serial, where + ": " + name);
    expect_converged(mpi, where + ": " + name);
  }
  if (solver_cost(name)) return;
  const double bound = name.rfind("kx", 0) == 0 ? kx_bound : kRelative;
  EXPECT_LE(relative_difference(serial, mpi), bound) << where << ": " << name;
}

std::string mpirun(int ranks) {
  return fretbem_test::mpiexec_command(ranks, 300);
}

std::string scenario(const std::string& name) {
  return (fs::path(FRETBEM_SOURCE_DIR) / "scenarios" / name).string();
}

// `fretbem run` on `ranks` ranks (0: without mpirun) into dir/out.
Result run(int ranks, const std::string& args, const fs::path& dir, const std::string& out) {
  const std::string launcher = ranks > 0 ? mpirun(ranks) : std::string();
  return shell(
      launcher + FRETBEM_BINARY + " run " + args + " --quiet --out " + (dir / out).string(), dir);
}

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (std::size_t p = 0; (p = text.find(what, p)) != std::string::npos; ++p) ++n;
  return n;
}

// Largest |a - b| relative to the largest |a| (NaN agrees with NaN only).
double relative_difference(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return INFINITY;
  double scale = 0.0, diff = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::isnan(a[i]) || std::isnan(b[i])) {
      if (std::isnan(a[i]) != std::isnan(b[i])) return INFINITY;
      continue;
    }
    scale = std::max(scale, std::abs(a[i]));
    diff = std::max(diff, std::abs(a[i] - b[i]));
  }
  return diff == 0.0 ? 0.0 : diff / scale;
}

void expect_same_table(const fs::path& serial, const fs::path& mpi, double kx_bound = kRelative) {
  const auto a = fretbem_test::csv_columns(serial), b = fretbem_test::csv_columns(mpi);
  ASSERT_FALSE(a.empty()) << serial;
  ASSERT_EQ(a.size(), b.size()) << mpi;
  for (const auto& [name, values] : a) {
    ASSERT_TRUE(b.count(name)) << mpi << ": no column " << name;
    expect_same_values(name, values, b.at(name), mpi.string(), kx_bound);
  }
}

// Every numeric dataset of an HDF5 file, by path, as doubles.
herr_t collect(hid_t file, const char* name, const H5O_info_t* info, void* data) {
  if (info->type != H5O_TYPE_DATASET) return 0;
  const hid_t d = H5Dopen2(file, name, H5P_DEFAULT);
  const hid_t t = H5Dget_type(d);
  const H5T_class_t c = H5Tget_class(t);
  if (c == H5T_INTEGER || c == H5T_FLOAT) {
    const hid_t s = H5Dget_space(d);
    std::vector<double> v(std::size_t(H5Sget_simple_extent_npoints(s)));
    H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
    H5Sclose(s);
    (*static_cast<std::map<std::string, std::vector<double>>*>(data))[name] = v;
  }
  H5Tclose(t);
  H5Dclose(d);
  return 0;
}

std::map<std::string, std::vector<double>> datasets(const fs::path& h5) {
  std::map<std::string, std::vector<double>> out;
  const hid_t f = H5Fopen(h5.string().c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return out;
  H5Ovisit(f, H5_INDEX_NAME, H5_ITER_INC, collect, &out);
  H5Fclose(f);
  return out;
}

// timeseries.csv, cycles.csv and result.h5 of two run folders, to kRelative (k_x columns to
// kx_bound).
void expect_same_run(const fs::path& serial, const fs::path& mpi, double kx_bound = kRelative,
                     double field_bound = kRelative) {
  expect_same_table(serial / "timeseries.csv", mpi / "timeseries.csv", kx_bound);
  expect_same_table(serial / "cycles.csv", mpi / "cycles.csv", kx_bound);
  const auto a = datasets(serial / "result.h5"), b = datasets(mpi / "result.h5");
  ASSERT_GT(a.size(), 3u) << "fields written";
  ASSERT_EQ(a.size(), b.size());
  for (const auto& [name, values] : a) {
    ASSERT_TRUE(b.count(name)) << mpi << ": no dataset " << name;
    // /timeseries holds the columns of /series/timeseries/NAME, compared one by one.
    if (name == "timeseries") continue;
    const bool field = name.rfind("series/timeseries", 0) != 0;
    if (field && field_bound > kRelative) {
      EXPECT_LE(relative_difference(values, b.at(name)), field_bound) << mpi << ": " << name;
      continue;
    }
    expect_same_values(fs::path(name).filename().string(), values, b.at(name),
                       (mpi / "result.h5").string(), kx_bound);
  }
}

// A Mindlin cycle at n = 32 (contact radius ~8 cells) with traction, state, slip and
// dissipation fields every 4 steps.
std::string small_mindlin() {
  return scenario("mindlin_cycle.ini") +
         " --set grid.n=32 --set load.cycles=2 --set load.steps_per_cycle=16"
         " --set output.fields=pressure,traction_x,state,slip_x,dissipation"
         " --set output.fields_every=4 --set solver.tolerance=1e-12";
}

std::string small_rough() {
  return scenario("rough_fretting_cycle.ini") +
         " --set grid.n=32 --set output.fields=pressure,traction_x,state,dissipation"
         " --set solver.tolerance=1e-12";
}

// `args` run serially, then on two ranks and on three: the files equal, and the summary's
// line `summary` is printed once.
void expect_same_on_ranks(const std::string& args, const std::string& name,
                          const std::string& summary = "steps done") {
  const fs::path d = scratch(name);
  const Result s = run(0, args, d, "serial");
  ASSERT_EQ(s.status, 0) << s.err;
  for (int ranks : {2, 3}) {
    const std::string out = "mpi" + std::to_string(ranks);
    const Result m = run(ranks, args, d, out);
    ASSERT_EQ(m.status, 0) << m.err;
    EXPECT_EQ(count(m.out, summary), 1) << "one rank prints: " << m.out;
    expect_same_run(d / "serial", d / out);
  }
}

// A short wear run at n = 32 to N = 200 with the state and wear fields: fretting_wear.ini (a
// Hertz partial-slip contact, Archard, arkode: explicit steps and stretches of cycles one by
// one) or rough_fretting_wear.ini (a rough surface, the energy law).
std::string small_wear(const std::string& ini) {
  return scenario(ini) +
         " --set grid.n=32 --set wear.cycles=200 --set solver.tolerance=1e-12"
         " --set output.fields=pressure,traction_x,state,slip_x,dissipation,wear";
}
}  // namespace

TEST(RunMpi, MindlinCycleOnTwoAndThreeRanksEqualsSerial) {
  expect_same_on_ranks(small_mindlin(), "run_mpi_mindlin");
}

TEST(RunMpi, RoughFrettingCycleOnTwoAndThreeRanksEqualsSerial) {
  expect_same_on_ranks(small_rough(), "run_mpi_rough");
}

// Error-controlled steps (load.tolerance): the step-doubling estimate and the sub-steps it
// asks for are taken from the reduced forces and shifts, alike on every rank.
TEST(RunMpi, StepControlOnTwoRanksEqualsSerial) {
  const fs::path d = scratch("run_mpi_step_control");
  const std::string args = scenario("mindlin_cycle.ini") +
                           " --set grid.n=32 --set load.cycles=1 --set load.steps_per_cycle=8"
                           " --set load.tolerance=1e-3 --set solver.tolerance=1e-12"
                           " --set output.fields=traction_x,dissipation";
  const Result s = run(0, args, d, "serial");
  ASSERT_EQ(s.status, 0) << s.err;
  const Result m = run(2, args, d, "mpi");
  ASSERT_EQ(m.status, 0) << m.err;
  expect_same_run(d / "serial", d / "mpi");
}

namespace {

// Runs ARGS (which stop early) on `stopped_on` ranks into D/OUT, resumes it on `resumed_on`
// (0: serially) and compares it with the uninterrupted serial run in D/serial.
void stop_and_resume(const fs::path& d, const std::string& args, int stopped_on, int resumed_on,
                     const std::string& out, double kx_bound = kResumedKx,
                     double field_bound = kRelative) {
  const Result stopped = run(stopped_on, args, d, out);
  ASSERT_EQ(stopped.status, 0) << stopped.err;
  ASSERT_TRUE(fs::exists(d / out / "checkpoint.h5"));
  const std::string launcher = resumed_on > 0 ? mpirun(resumed_on) : std::string();
  const Result r =
      shell(launcher + FRETBEM_BINARY + " run --quiet --resume " + (d / out).string(), d);
  ASSERT_EQ(r.status, 0) << r.err;
  expect_same_run(d / "serial", d / out, kx_bound, field_bound);
}

}  // namespace

// --stop-after stops the run after a given step, checkpointed: the resumed run's files equal
// the uninterrupted serial run's, stopped on two ranks and resumed on the same two, on three
// and serially, and stopped serially and resumed on two.
TEST(RunMpi, ResumeOnRanksEqualsUninterruptedRun) {
  const fs::path d = scratch("run_mpi_resume");
  const Result s = run(0, small_mindlin(), d, "serial");
  ASSERT_EQ(s.status, 0) << s.err;
  // (ranks that stop, ranks that resume; 0: serial)
  for (const auto& [stopped_on, resumed_on] :
       std::vector<std::pair<int, int>>{{2, 2}, {2, 3}, {2, 0}, {0, 2}}) {
    stop_and_resume(
        d, small_mindlin() + " --stop-after 13", stopped_on, resumed_on,
        "stopped" + std::to_string(stopped_on) + "_resumed" + std::to_string(resumed_on));
  }
}

namespace {

// The table F_z = P (1 + 0.3 sin 2 pi t), F_x = 0.5 mu P cos 2 pi t (P = 10 N) at `rows` rows
// a period over two periods, on the steel sphere of mindlin_cycle.ini at n = 32 (contact radius
// about 8 cells) with `interpolation`, solved to 1e-12, writing `fields`: writes
// D/tableROWS.csv and the scenario, and returns the scenario's path.
std::string sine_table_scenario(const fs::path& d, int rows, const std::string& interpolation,
                                const std::string& fields = "traction_x,dissipation") {
  const std::string name = "table" + std::to_string(rows);
  fretbem_test::write_sine_normal_table(d / (name + ".csv"), rows, 10.0, 0.5, 2);
  const fs::path ini = d / (name + interpolation + ".ini");
  std::ofstream(ini)
      << "[material]\nE = 210e9\nnu = 0.3\nmu = 0.5\n[grid]\nn = 32\nlength = 2.8e-4\n"
         "[surface]\ntype = sphere\nradius = 0.01\n[load]\npath = table\ntable = "
      << (d / (name + ".csv")).string() << "\ninterpolation = " << interpolation
      << "\n[solver]\ntolerance = 1e-12\n[output]\nfields = " << fields << "\n";
  return ini.string();
}

// Column `name` of DIR/cycles.csv.
std::vector<double> cycle_column(const fs::path& dir, const std::string& name) {
  return fretbem_test::csv_columns(dir / "cycles.csv")[name];
}

// slip_area_at_peak of each cycle c is the slip area of its first turning point of largest
// |F_x|: on the sampled cosine the row at t = c + 1/2 (F_x = -0.5 mu P, reached before
// +0.5 mu P at t = c + 1), a count of nodes times the cell area, equal exactly to the serial
// run's in `serial`.
void expect_first_peak(const fs::path& serial, const fs::path& dir) {
  auto ts = fretbem_test::csv_columns(dir / "timeseries.csv");
  const auto peaks = cycle_column(dir, "slip_area_at_peak"), cycle = cycle_column(dir, "cycle");
  ASSERT_FALSE(peaks.empty()) << dir;
  EXPECT_EQ(peaks, cycle_column(serial, "slip_area_at_peak")) << dir;
  int found = 0;
  for (std::size_t c = 0; c < peaks.size(); ++c)
    for (std::size_t k = 0; k < ts["time"].size(); ++k)
      if (ts["time"][k] == cycle[c] + 0.5) {
        ++found;
        EXPECT_EQ(ts["turning"][k], 1.0) << dir << ": t = " << ts["time"][k];
        EXPECT_EQ(peaks[c], ts["slip_area"][k]) << dir << ": cycle " << cycle[c];
      }
  EXPECT_EQ(found, 2) << dir << ": the turning points t = 1/2 and 3/2";
}

// ARGS (rows in sub-steps) serially into D/serial and on two ranks into D/mpi: the same run, the
// fields to kSubstepFields and k_x to kLayoutKx.
void expect_sub_stepped_two_ranks(const fs::path& d, const std::string& args) {
  const Result s = run(0, args, d, "serial");
  ASSERT_EQ(s.status, 0) << s.err;
  const Result m = run(2, args, d, "mpi");
  ASSERT_EQ(m.status, 0) << m.err;
  expect_same_run(d / "serial", d / "mpi", kLayoutKx, kSubstepFields);
}

}  // namespace

// load.interpolation = cubic on a table whose normal load varies (20 rows a period of the
// sampled sine, two periods, F_z about 10 N on a steel sphere at n = 32), every row in the
// default sub-steps (load.substeps): the three-point rule's memory of the step before is per
// node, split in slabs like every field, and in the checkpoint. Two ranks equal the serial run;
// stopped and resumed on two ranks, the uninterrupted serial one; stopped on two ranks after the
// period's second turning point of |F_x| = 0.5 mu P (t = 1) and resumed serially, too: the
// cycle's rows come from both layouts, its peak is still the serial run's row.
TEST(RunMpi, CubicTableOnTwoRanksEqualsSerialAndResumes) {
  const fs::path d = scratch("run_mpi_cubic");
  const std::string args = sine_table_scenario(d, 20, "cubic");
  expect_sub_stepped_two_ranks(d, args);
  stop_and_resume(d, args + " --stop-after 11", 2, 2, "stopped2_resumed2", kLayoutKx,
                  kSubstepFields);
  stop_and_resume(d, args + " --stop-after 21", 2, 0, "stopped2_resumed0", kLayoutKx,
                  kSubstepFields);
  for (const char* out : {"mpi", "stopped2_resumed2", "stopped2_resumed0"})
    expect_first_peak(d / "serial", d / out);
}

// The same table, linear, in the default sub-steps: the second period's sub-steps start from the
// first period's (the cycle predictor remembers every sub-step of a row the path repeats), whose
// entries hold every rank's nodes and are gathered into the checkpoint and sliced from it. Two
// ranks equal the serial run; stopped on two ranks in the second period (after 22 rows: its
// first rows started from the predictor) and resumed on two ranks and serially, too.
TEST(RunMpi, PredictedSubstepsOnTwoRanksEqualSerialAndResume) {
  const fs::path d = scratch("run_mpi_predicted_substeps");
  const std::string args = sine_table_scenario(d, 16, "linear");
  expect_sub_stepped_two_ranks(d, args);
  for (const int ranks : {2, 0})
    stop_and_resume(d, args + " --stop-after 22", 2, ranks,
                    "stopped2_resumed" + std::to_string(ranks), kLayoutKx, kSubstepFields);
}

// load.tolerance on the same table (16 rows a period, linear), where every row's normal load
// varies: the sub-steps of each row come from the estimate summed over every rank's nodes and
// from the period's rate (history/step_control.hpp), alike on every layout. Two ranks equal
// the serial run; stopped on two ranks within the first period (the rate not yet a whole
// period's: rows may be solved again) and resumed on two ranks, too; and stopped after row 0
// (the normal load alone: no step estimated, so no estimate memory in the checkpoint).
TEST(RunMpi, StepControlOnAVaryingTableOnTwoRanksEqualsSerialAndResumes) {
  const fs::path d = scratch("run_mpi_step_control_table");
  const std::string args = sine_table_scenario(d, 16, "linear") + " --set load.tolerance=1e-3";
  expect_sub_stepped_two_ranks(d, args);
  for (const int stop : {7, 1})
    stop_and_resume(d, args + " --stop-after " + std::to_string(stop), 2, 2,
                    "stopped2_resumed2_after" + std::to_string(stop), kLayoutKx, kSubstepFields);
}

// The table reaches |F_x| = 0.5 mu P at two turning points a period, after different F_z
// histories (88 slip nodes at t = c + 1/2, none at t = c + 1), and the force projection holds
// both to round-off, which the ranks change: which is the cycle's peak is decided alike on
// every layout (history/resolution.hpp, kSameLoad). 16 rows a period linear and 12 cubic (a
// plain comparison of the two |F_x| takes the other row on two ranks, in cycle 1 and cycle 0):
// two ranks equal the serial run. The fields are the node states and the dissipation.
TEST(RunMpi, TablePeaksOnTwoRanksEqualSerial) {
  const fs::path d = scratch("run_mpi_table_peaks");
  for (const auto& [rows, interpolation] :
       std::vector<std::pair<int, std::string>>{{16, "linear"}, {12, "cubic"}}) {
    const std::string args = sine_table_scenario(d, rows, interpolation, "state,dissipation");
    const std::string name = std::to_string(rows) + interpolation;
    const Result s = run(0, args, d, "serial" + name);
    ASSERT_EQ(s.status, 0) << s.err;
    const Result m = run(2, args, d, "mpi" + name);
    ASSERT_EQ(m.status, 0) << m.err;
    expect_same_run(d / ("serial" + name), d / ("mpi" + name), kLayoutKx);
    expect_first_peak(d / ("serial" + name), d / ("serial" + name));
    expect_first_peak(d / ("serial" + name), d / ("mpi" + name));
  }
}

// Wear runs: cycles.csv, the wear snapshots and final fields of result.h5 too.
TEST(RunMpi, WearRunsOnTwoAndThreeRanksEqualSerial) {
  expect_same_on_ranks(small_wear("fretting_wear.ini"), "run_mpi_wear", "fretbem: wear to N");
  expect_same_on_ranks(small_wear("rough_fretting_wear.ini"), "run_mpi_rough_wear",
                       "fretbem: wear to N");
}

// A wear run stopped on two ranks after a few wear steps (the explicit integrator's accepted
// steps; cycle by cycle: simulated cycles) and resumed on two, on three and serially equals the
// uninterrupted serial run.
TEST(RunMpi, WearResumeOnRanksEqualsUninterruptedRun) {
  const fs::path d = scratch("run_mpi_wear_resume");
  for (const std::string& args : {small_wear("fretting_wear.ini"),
                                  small_wear("fretting_wear.ini") + " --set wear.cycles=10"}) {
    const Result s = run(0, args, d, "serial");
    ASSERT_EQ(s.status, 0) << s.err;
    for (int resumed_on : {2, 3, 0}) {
      const std::string out = "resumed" + std::to_string(resumed_on);
      fs::remove_all(d / out);
      stop_and_resume(d, args + " --stop-after 4", 2, resumed_on, out);
    }
    fs::remove_all(d / "serial");
  }
}

// The processes whose parent is `parent` and whose name is fretbem: the ranks mpirun started.
std::vector<pid_t> ranks_of(pid_t parent) {
  std::vector<pid_t> out;
  for (const auto& e : fs::directory_iterator("/proc")) {
    const std::string id = e.path().filename().string();
    if (id.find_first_not_of("0123456789") != std::string::npos) continue;
    std::istringstream stat(slurp(e.path() / "stat"));
    std::string line;
    std::getline(stat, line);
    const auto close = line.rfind(')');
    if (close == std::string::npos || slurp(e.path() / "comm") != "fretbem\n") continue;
    std::istringstream rest(line.substr(close + 1));
    char state = 0;
    long ppid = 0;
    if (rest >> state >> ppid && ppid == parent) out.push_back(pid_t(std::stol(id)));
  }
  return out;
}

// SIGTERM to one rank (a batch system's signal may reach the ranks at different steps): every
// rank stops after the same step, rank 0 writes the checkpoint and says so once, all exit 143,
// and the run resumed on two ranks equals the uninterrupted serial run.
TEST(RunMpi, SignalToOneRankStopsAllAndResumes) {
  const fs::path d = scratch("run_mpi_signal");
  const Result s = run(0, small_mindlin(), d, "serial");
  ASSERT_EQ(s.status, 0) << s.err;
  std::vector<std::string> argv{
      FRETBEM_MPIEXEC, "--allow-run-as-root", "--oversubscribe", "-n", "2", FRETBEM_BINARY, "run"};
  std::istringstream words(small_mindlin() + " --quiet --out " + (d / "sig").string());
  for (std::string w; words >> w;) argv.push_back(w);
  const std::string session = fretbem_test::mpi_session_base();
  const pid_t mpirun_pid = fork();
  if (mpirun_pid == 0) {
    ::setenv("OMPI_MCA_orte_tmpdir_base", session.c_str(), 1);
    const int e = ::open((d / "err").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (e < 0 || ::dup2(e, 2) < 0) ::_exit(126);
    std::vector<char*> args;
    for (auto& a : argv) args.push_back(a.data());
    args.push_back(nullptr);
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  std::vector<pid_t> ranks;
  int status = 0;
  ASSERT_TRUE(fretbem_test::wait_until(
      mpirun_pid,
      [&] {
        ranks = ranks_of(mpirun_pid);
        const std::string rows = slurp(d / "sig" / "timeseries.csv");
        return ranks.size() == 2 && std::count(rows.begin(), rows.end(), '\n') >= 4;
      },
      &status))
      << "the run ended before its third step";
  ::kill(ranks.back(), SIGTERM);
  EXPECT_EQ(fretbem_test::wait_exit(mpirun_pid), 143);
  const std::string err = slurp(d / "err");
  EXPECT_EQ(count(err, "fretbem: stopped by SIGTERM"), 1) << err;
  const Result r =
      shell(mpirun(2) + FRETBEM_BINARY + " run --quiet --resume " + (d / "sig").string(), d);
  ASSERT_EQ(r.status, 0) << r.err;
  expect_same_run(d / "serial", d / "sig", kResumedKx);
}

// A refusal on two ranks: one line (rank 0's), the same exit code, nothing left running.
TEST(RunMpi, RefusalOnTwoRanksIsOneLine) {
  const fs::path d = scratch("run_mpi_refused");
  const Result bad = run(2, small_mindlin() + " --set material.mu=-1", d, "bad");
  EXPECT_EQ(bad.status, 2) << bad.err;
  EXPECT_EQ(count(bad.err, "fretbem: error:"), 1) << bad.err;
  EXPECT_EQ(count(bad.err, "material.mu"), 1) << bad.err;
  const Result kinetic = run(2,
                             small_wear("fretting_wear.ini") +
                                 " --set friction.law=static_kinetic --set friction.mu_kinetic=0.4",
                             d, "kinetic");
  EXPECT_EQ(kinetic.status, 2) << kinetic.err;
  EXPECT_EQ(count(kinetic.err, "fretbem: error: friction.law under mpirun -n 2"), 1) << kinetic.err;
  EXPECT_FALSE(fs::exists(d / "kinetic" / "timeseries.csv"));
  // A refusal only rank 0 can make (it alone looks into the folder) ends every rank alike.
  ASSERT_EQ(run(0, small_mindlin(), d, "taken").status, 0);
  const Result taken = run(2, small_mindlin(), d, "taken");
  EXPECT_EQ(taken.status, 2) << taken.err;
  EXPECT_EQ(count(taken.err, "fretbem: error:"), 1) << taken.err;
  EXPECT_EQ(count(taken.err, "holds the results of another run"), 1) << taken.err;
  // The edge-contact refusal comes from the distributed normal solve of step 0, on every rank.
  const Result edge = run(2, small_mindlin() + " --set grid.length=1.2e-4", d, "edge");
  EXPECT_EQ(edge.status, 2) << edge.err;
  EXPECT_EQ(count(edge.err, "fretbem: error:"), 1) << edge.err;
}

TEST(RunMpi, OneRankIsASerialRun) {
  const fs::path d = scratch("run_mpi_one");
  const std::string args = " run " + scenario("mindlin_cycle.ini") +
                           " --quiet --set grid.n=16 --set load.cycles=1 --set "
                           "load.steps_per_cycle=8 --out ";
  const Result s = shell(std::string(FRETBEM_BINARY) + args + (d / "serial").string(), d);
  ASSERT_EQ(s.status, 0) << s.err;
  const Result m = shell(mpirun(1) + FRETBEM_BINARY + args + (d / "mpi").string(), d);
  ASSERT_EQ(m.status, 0) << m.err;
  EXPECT_EQ(slurp(d / "serial" / "timeseries.csv"), slurp(d / "mpi" / "timeseries.csv"));
}
