// fretbem command line: run | check | surface (README "Command line").
#include <algorithm>
#include <boost/program_options.hpp>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <new>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/hdf5.hpp"
#include "fretbem/core/input_warning.hpp"
#include "fretbem/core/resources.hpp"
#include "fretbem/core/stop_signal.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/io/failed_solve.hpp"
#include "fretbem/parallel/communicator.hpp"
#include "fretbem/run/check.hpp"
#include "fretbem/run/run.hpp"
#include "fretbem/scenario/ignored_keys.hpp"
#include "fretbem/scenario/scenario.hpp"
#include "fretbem/study/ensemble.hpp"
#include "fretbem/study/sweep.hpp"
#include "fretbem/surface/surface.hpp"

namespace po = boost::program_options;
using namespace fretbem;

namespace {

constexpr const char* kUsage =
    "fretbem " FRETBEM_VERSION
    " — frictional contact of rough elastic surfaces under load histories\n\n"
    "usage:\n"
    "  fretbem run SCENARIO.ini [--set section.key=value ...] [--out DIR] [--overwrite]\n"
    "              [--quiet]   (--overwrite: replace another run's results in DIR)\n"
    "  fretbem run --resume DIR [--quiet]   (continue an interrupted run)\n"
    "  run options: --stop-after N  run at most N steps, checkpoint, exit (resume later);\n"
    "               wear runs: N simulated cycles (wear.integrator = cycle) or accepted\n"
    "               integrator steps (ARKODE)\n"
    "  fretbem check SCENARIO.ini [--set section.key=value ...] [--no-estimate]\n"
    "              (the cost estimate solves the first steps; --no-estimate skips it)\n"
    "  fretbem surface [SCENARIO.ini] [--set surface.key=value ...] --out FILE\n"
    "  fretbem ensemble SCENARIO.ini --hurst H1,H2,... [--seeds N] [--jobs J] [--bins B]\n"
    "                   [--set section.key=value ...] [--out DIR] [--overwrite] [--quiet]\n"
    "  fretbem sweep STUDY.ini [--jobs J] [--set section.key=value ...] [--out DIR] [--quiet]\n"
    "                [--list | --member K | --aggregate]   (docs/sweep.md; under mpirun:\n"
    "                members spread over the ranks, docs/cluster.md)\n"
    "  mpirun -n K fretbem run ...   one grid split over K ranks (MPI builds, docs/mpi-grid.md)\n"
    "  fretbem --help | --version\n\n"
    "Scenario keys, output columns and conventions: see README.md.\n";

// A minimal rough-surface scenario for `fretbem surface` without a scenario file.
constexpr const char* kSurfaceDefaults =
    "[material]\nE = 1\nnu = 0\n[grid]\nn = 256\nlength = 1\n"
    "[surface]\ntype = rough\nhurst = 0.8\nmethod = fourier\nseed = 1\n"
    "[load]\nnormal_force = 1\n";

// A run on a grid distributed over ranks: rank 0 prints its error line, the other ranks
// (which raise the same error) only exit with its code; a failed solve's inputs are slabs,
// not saved.
bool g_silent_rank = false;
bool g_distributed_run = false;

struct Args {
  std::string command, scenario, out, resume;
  long stop_after = -1;
  std::vector<std::string> sets;
  bool quiet = false;
  bool overwrite = false;
  bool out_given = false;
  bool estimate = true;                  // check: calibrate and print the cost estimate
  std::string hurst;                     // ensemble
  int seeds = 20, jobs = 0, bins = 20;   // ensemble (jobs also sweep)
  bool list = false, aggregate = false;  // sweep
  long member = -1;                      // sweep
};

// Options of one command given to another must not be ignored without a word (`fretbem sweep
// S --seeds 5`, `fretbem run S --jobs 4`). `check` takes `run`'s options
// too, so that a run's command line can be checked as it is.
void refuse_foreign_options(const std::string& command, const po::variables_map& vm) {
  static const std::map<std::string, std::set<std::string>> kOptions{
      {"run", {"set", "out", "quiet", "overwrite", "resume", "stop-after"}},
      {"check", {"set", "out", "quiet", "overwrite", "stop-after", "no-estimate"}},
      {"surface", {"set", "out", "quiet"}},
      {"ensemble", {"set", "out", "quiet", "overwrite", "hurst", "seeds", "jobs", "bins"}},
      {"sweep", {"set", "out", "quiet", "jobs", "list", "aggregate", "member"}}};
  const auto it = kOptions.find(command);
  if (it == kOptions.end()) return;  // help, version, or an unknown command (refused later)
  for (const auto& [name, value] : vm)
    if (name != "positional" && name != "help" && name != "version" && !it->second.count(name))
      throw InputError("--" + name + " is not an option of `fretbem " + command +
                       "` (fretbem --help lists each command's options)");
}

Args parse_args(int argc, char** argv) {
  po::options_description opts("options");
  opts.add_options()("help,h", "")("version", "")("set", po::value<std::vector<std::string>>(), "")(
      "out", po::value<std::string>(), "")("quiet,q", "")("overwrite", "")(
      "resume", po::value<std::string>(), "")("stop-after", po::value<long>(), "")(
      "hurst", po::value<std::string>(), "")("seeds", po::value<int>(), "")(
      "jobs", po::value<int>(), "")("bins", po::value<int>(), "")("list", "")("aggregate", "")(
      "no-estimate", "")("member", po::value<long>(), "")(
      "positional", po::value<std::vector<std::string>>(), "");
  po::positional_options_description pos;
  pos.add("positional", -1);
  po::variables_map vm;
  po::store(po::command_line_parser(argc, argv).options(opts).positional(pos).run(), vm);
  Args a;
  if (vm.count("help")) a.command = "help";
  if (vm.count("version")) a.command = "version";
  if (vm.count("set")) a.sets = vm["set"].as<std::vector<std::string>>();
  if (vm.count("out")) {
    a.out = vm["out"].as<std::string>(), a.out_given = true;
    if (a.out.empty()) throw InputError("--out: empty directory name");
  }
  a.overwrite = vm.count("overwrite") > 0;
  a.quiet = vm.count("quiet") > 0;
  a.estimate = vm.count("no-estimate") == 0;
  if (vm.count("resume")) a.resume = vm["resume"].as<std::string>();
  if (vm.count("stop-after")) {
    a.stop_after = vm["stop-after"].as<long>();
    if (a.stop_after < 1) throw InputError("--stop-after must be at least 1");
  }
  if (vm.count("hurst")) a.hurst = vm["hurst"].as<std::string>();
  if (vm.count("seeds")) a.seeds = vm["seeds"].as<int>();
  if (vm.count("jobs")) a.jobs = vm["jobs"].as<int>();
  if (vm.count("bins")) a.bins = vm["bins"].as<int>();
  a.list = vm.count("list") > 0, a.aggregate = vm.count("aggregate") > 0;
  if (vm.count("member")) {
    a.member = vm["member"].as<long>();
    if (a.member < 0) throw InputError("--member must be a member index >= 0");
  }
  const auto p = vm.count("positional") ? vm["positional"].as<std::vector<std::string>>()
                                        : std::vector<std::string>{};
  if (a.command.empty()) {
    if (p.empty()) throw InputError("no command given (try: fretbem --help)");
    a.command = p[0];
  }
  if (p.size() > 2) throw InputError("unexpected argument '" + p[2] + "'");
  if (p.size() == 2) a.scenario = p[1];
  refuse_foreign_options(a.command, vm);
  return a;
}

// Each distinct caution once: check's calibration prepares the model again.
void print_input_warnings_once() {
  set_input_warning_handler([seen = std::set<std::string>()](const std::string& w) mutable {
    if (seen.insert(w).second) std::fprintf(stderr, "fretbem: warning: %s\n", w.c_str());
  });
}

// A scenario file read by `run`, `check` or `surface`: its input cautions are printed (a resumed
// run's were printed when it started), and `run` and `check` warn alike about every given key
// the scenario's choices leave unread.
Scenario read_scenario(const Args& a) {
  if (a.scenario.empty()) throw InputError(a.command + ": no scenario file given");
  if (launched_rank() == 0) print_input_warnings_once();
  Scenario sc = load_scenario(a.scenario, a.sets);
  if (a.command == "run" || a.command == "check")
    for (const auto& w : ignored_key_warnings(sc)) input_warning(w);
  return sc;
}

RunOptions run_options(const Args& a) {
  return {.quiet = a.quiet, .overwrite = a.overwrite, .stop_after = a.stop_after};
}

// Resume takes the run's own scenario and folder: options that would change either are
// refused.
int cmd_resume(const Args& a, const Communicator& comm) {
  if (!a.scenario.empty() || !a.sets.empty())
    throw InputError("run --resume DIR takes no scenario or --set: the run's own is used");
  if (a.out_given)
    throw InputError("run --resume DIR continues in DIR: --out is not allowed with it");
  if (a.overwrite) throw InputError("run --resume DIR: --overwrite is not allowed with it");
  return resume_run(a.resume, run_options(a), comm);
}

// Under mpirun -n K > 1 one grid is distributed over the ranks (docs/mpi-grid.md): every rank
// reads and validates the scenario alike, rank 0 alone writes files and prints (the other
// ranks' warnings and error lines are rank 0's too, and are not repeated).
int cmd_run(const Args& a) {
  const Communicator& comm =
      launched_on_several_ranks() ? world_communicator() : serial_communicator();
  g_distributed_run = comm.distributed();
  g_silent_rank = comm.rank() != 0;
  if (g_silent_rank) set_input_warning_handler([](const std::string&) {});
  install_stop_signal_handlers(SecondSignal::kills);  // stop at the next step, checkpointed
  if (!a.resume.empty()) return cmd_resume(a, comm);
  Scenario sc = read_scenario(a);
  if (!a.out.empty()) set_output_dir(sc, a.out);
  return run_scenario(sc, run_options(a), comm);
}

int cmd_check(const Args& a) {
  Scenario sc = read_scenario(a);
  if (!a.out.empty()) set_output_dir(sc, a.out);
  return check_scenario(sc, a.scenario, {.overwrite = a.overwrite, .estimate = a.estimate});
}

// The default scale (rms height 1 mm of a 1 m domain) applies only when neither scale is set:
// a user's surface.rms_slope must not meet a hidden rms_height.
std::vector<std::string> with_default_scale(std::vector<std::string> sets) {
  const bool scaled = std::any_of(sets.begin(), sets.end(), [](const std::string& s) {
    return s.rfind("surface.rms_height", 0) == 0 || s.rfind("surface.rms_slope", 0) == 0;
  });
  if (!scaled) sets.insert(sets.begin(), "surface.rms_height=1e-3");
  return sets;
}

int cmd_surface(const Args& a) {
  if (a.out.empty()) throw InputError("surface: --out FILE is required");
  const Scenario sc = a.scenario.empty() ? parse_scenario(kSurfaceDefaults, "surface", ".",
                                                          with_default_scale(a.sets))
                                         : read_scenario(a);
  const Field z = make_surface(sc);
  save_height_map(a.out, z, sc.grid.h);
  const SurfaceStats st = surface_statistics(sc.grid, z);
  std::printf("surface %s: %d x %d, h = %g m\n", a.out.c_str(), sc.grid.nx, sc.grid.ny, sc.grid.h);
  std::printf("  rms height %.6g m\n  rms slope  %.6g\n  min %.6g m  max %.6g m\n", st.rms_height,
              st.rms_slope, st.min, st.max);
  std::printf("  Hurst exponent fitted to the PSD: %.3f\n", st.hurst_fit);
  if (st.hurst_fit_octaves < kMinHurstFitOctaves)
    std::fprintf(stderr,
                 "fretbem: warning: the Hurst fit rests on %.1f octave(s) of wavelengths "
                 "(q from 4 to n/8 times 2 pi/L); below %.0f octaves fits of the same surface "
                 "statistics scatter by up to +-0.75: use n >= 128 to measure H\n",
                 std::max(st.hurst_fit_octaves, 0.0), kMinHurstFitOctaves);
  return 0;
}

int run_command_line(int argc, char** argv);

// A member's `fretbem run` command line run in this process (a study's worker process).
int run_member_command(const std::vector<std::string>& args) {
  std::vector<std::string> copy = args;
  std::vector<char*> argv;
  for (auto& s : copy) argv.push_back(s.data());
  argv.push_back(nullptr);
  return run_command_line(int(copy.size()), argv.data());
}

// Members run in --jobs worker processes of this one; exit 4 when any of them is not ok (failed, or
// still run by a killed ensemble's orphan), 143 when a signal stopped the ensemble
// (members.csv and aggregate.csv written anyway).
int cmd_ensemble(const Args& a) {
  // Its members are --jobs processes on one node: K copies of the ensemble would race for one
  // folder, the second refused by the folder's lock and mpirun then ending the first. Refused
  // before anything is written; rank 0 prints the line.
  if (launched_on_several_ranks()) {
    g_silent_rank = launched_rank() != 0;
    throw InputError(
        "fretbem ensemble under mpirun -n K > 1: its members run as --jobs processes on one "
        "node; start it without mpirun, or spread members over ranks with `fretbem sweep` "
        "(docs/cluster.md)");
  }
  if (a.scenario.empty()) throw InputError("ensemble: no scenario file given");
  EnsembleOptions o;
  o.scenario = a.scenario;
  o.sets = a.sets;
  o.hurst = parse_hurst_list(a.hurst);
  o.seeds = a.seeds, o.jobs = a.jobs, o.bins = a.bins;
  o.out = a.out;
  o.quiet = a.quiet;
  o.overwrite = a.overwrite;
  o.in_process = run_member_command;
  const int not_ok = run_ensemble(o);
  if (not_ok == kEnsembleStopped) return 143;  // as `fretbem sweep`: 128 + SIGTERM
  if (not_ok)
    std::fprintf(stderr,
                 "fretbem ensemble: %d member(s) not ok (failed, or run by another process; "
                 "members.csv says which)\n",
                 not_ok);
  return not_ok ? 4 : 0;
}

// Exit 4 when members failed, 143 when a signal stopped the study (sweep.csv written anyway).
int cmd_sweep(const Args& a) {
  if (a.scenario.empty()) throw InputError("sweep: no study file given");
  SweepCommand c;
  c.study = a.scenario, c.sets = a.sets, c.out = a.out;
  c.list = a.list, c.member = a.member, c.aggregate = a.aggregate;
  c.options.jobs = a.jobs, c.options.quiet = a.quiet;
  c.options.in_process = run_member_command;
  return run_sweep_command(c);
}

// "filesystem error: cannot rename: Is a directory [a] [b]" as "cannot rename a to b: Is a
// directory": the library's text names neither file plainly.
std::string describe(const std::filesystem::filesystem_error& e) {
  std::string op = e.what();
  const std::string prefix = "filesystem error: ";
  if (op.rfind(prefix, 0) == 0) op = op.substr(prefix.size());
  op = op.substr(0, op.find(": "));
  std::string msg = op;
  if (!e.path1().empty()) msg += " " + e.path1().string();
  if (!e.path2().empty()) msg += " to " + e.path2().string();
  return msg + ": " + e.code().message();
}

// An error line on stderr, unless this rank repeats rank 0's.
template <class... T>
void say(const char* format, T... values) {
  if (!g_silent_rank) std::fprintf(stderr, format, values...);
}

// A command line's exit status, every error reported on stderr.
int run_command_line(int argc, char** argv) {
  try {
    const Args a = parse_args(argc, argv);
    if (a.command == "help") return std::fputs(kUsage, stdout), 0;
    if (a.command == "version") return std::puts("fretbem " FRETBEM_VERSION), 0;
    if (a.command == "run") return cmd_run(a);
    if (a.command == "check") return cmd_check(a);
    if (a.command == "surface") return cmd_surface(a);
    if (a.command == "ensemble") return cmd_ensemble(a);
    if (a.command == "sweep") return cmd_sweep(a);
    throw InputError("unknown command '" + a.command + "' (run, check, surface, ensemble, sweep)");
  } catch (const InputError& e) {
    say("fretbem: error: %s\n", e.what());
    return 2;
  } catch (const IncrementFailure& e) {
    // The inputs of the failed solve, so that it can be reproduced alone.
    std::string where;
    try {
      if (g_distributed_run) throw std::runtime_error("not saved by a run over MPI ranks");
      where = "; its inputs are in " + write_failed_solve(e.dir, e.inputs).string();
    } catch (const std::exception& w) {
      where = "; its inputs could not be saved: " + std::string(w.what());
    }
    say("\nfretbem: solver error: %s%s\n", e.what(), where.c_str());
    return 3;
  } catch (const SolverError& e) {
    say("\nfretbem: solver error: %s\n", e.what());
    return 3;
  } catch (const po::error& e) {
    say("fretbem: error: %s\n", e.what());
    return 2;
  } catch (const std::bad_alloc&) {
    say("%s",
        "fretbem: error: out of memory: the grid (grid.n, grid.nx x grid.ny), the load "
        "steps or the fields written need more memory than this machine has left\n");
    return 1;
  } catch (const std::filesystem::filesystem_error& e) {
    say("fretbem: error: %s\n", describe(e).c_str());
    return 1;
  } catch (const std::exception& e) {
    say("fretbem: error: %s\n", e.what());
    return 1;
  }
}

}  // namespace

int main(int argc, char** argv) {
  fretbem::hdf5::no_library_close_at_exit();  // a full disk must end in a message, not SIGSEGV
  fretbem::keep_freed_memory();
  return run_command_line(argc, argv);
}
