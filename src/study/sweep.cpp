#include "fretbem/study/sweep.hpp"

#include <algorithm>
#include <cstdio>
#include <iostream>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/stop_signal.hpp"
#include "fretbem/core/text_file.hpp"
#include "fretbem/history/resolution.hpp"
#include "fretbem/study/member_status.hpp"
#include "fretbem/study/mpi_queue.hpp"
#include "fretbem/study/sweep_aggregate.hpp"

namespace fretbem {

namespace fs = std::filesystem;

namespace {

constexpr int kExitFailed = 4, kExitStopped = 128 + 15;

// Single-quoted for a POSIX shell unless the word is plainly safe.
std::string shell_word(const std::string& w) {
  if (!w.empty() && w.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                        "0123456789_-+=.,/:@%") == std::string::npos)
    return w;
  std::string q = "'";
  for (char c : w) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// One `fretbem sweep STUDY --member K` line per member, with absolute paths, so that a Slurm
// array task or GNU parallel runs it from any directory.
void print_member_commands(const SweepCommand& cmd, const SweepSpec& spec) {
  for (std::size_t k = 0; k < spec.members.size(); ++k) {
    std::string line = shell_word(cmd.options.binary.string()) + " sweep " +
                       shell_word(fs::absolute(cmd.study).lexically_normal().string()) +
                       " --member " + std::to_string(k) + " --out " + shell_word(spec.out.string());
    for (const auto& s : cmd.sets) line += " --set " + shell_word(s);
    std::puts(line.c_str());
  }
}

// Writes sweep.csv and says how many members are in which state (always when some is not ok).
SweepTally aggregate(const SweepSpec& spec, bool quiet) {
  const SweepTally t = write_sweep_csv(spec);
  if (!quiet || t.ok != int(spec.members.size()))
    std::fprintf(stderr,
                 "fretbem sweep: %d ok, %d failed, %d running (in another process, or killed "
                 "while running), %d not run of %zu; %s\n",
                 t.ok, t.failed, t.running, t.missing, spec.members.size(),
                 (spec.out / "sweep.csv").c_str());
  return t;
}

// A study that ran its members succeeds only when every one of them is ok: a member left to
// another process (a run orphaned by a study killed outright, another study of the folder) has
// no result yet, and a script that reads exit 0 as "sweep.csv is complete" would go on without it.
int study_exit_code(const SweepSpec& spec, const SweepTally& t) {
  return t.ok == int(spec.members.size()) ? 0 : kExitFailed;
}

std::vector<std::size_t> one_member(const SweepSpec& spec, long k) {
  if (k < 0 || std::size_t(k) >= spec.members.size())
    throw InputError("--member " + std::to_string(k) + ": the study has members 0.." +
                     std::to_string(spec.members.size() - 1));
  if (member_complete(spec.study_members(), std::size_t(k))) return {};
  return {std::size_t(k)};
}

// One line before the members run when the study refined grids or some slip rings stay under
// two cells: the details are sweep.csv's grid_n, ring_cells_predicted and resolution.
void report_grids(const SweepSpec& spec) {
  int refined = 0, under = 0, max_n = 0;
  for (const auto& g : spec.grids) {
    refined += g.resolution.rfind("refined", 0) == 0;
    under += g.resolution.rfind("under-resolved", 0) == 0;
    if (g.n != g.base_n) max_n = std::max(max_n, g.n);
  }
  if (refined)
    std::fprintf(stderr,
                 "fretbem sweep: %d member(s) refined (up to grid.n = %d) so that the slip ring "
                 "spans %g cells\n",
                 refined, max_n, kMinRingCells);
  if (under && spec.max_grid_n)
    std::fprintf(stderr,
                 "fretbem sweep: %d member(s) keep a slip ring under %g cells even at "
                 "study.max_grid_n = %d (energy per cycle under-resolved); see resolution in "
                 "sweep.csv\n",
                 under, kMinRingCells, spec.max_grid_n);
  else if (under)
    std::fprintf(stderr,
                 "fretbem sweep: %d member(s) have a slip ring under %g cells (energy per cycle "
                 "under-resolved); set study.max_grid_n to refine them; see resolution in "
                 "sweep.csv\n",
                 under, kMinRingCells);
}

// --list, --aggregate or --member K.
int one_process_command(const SweepCommand& cmd, const SweepSpec& spec) {
  if (cmd.list) return print_member_commands(cmd, spec), 0;
  // --aggregate reports what has finished so far: only failed members make it unsuccessful.
  if (cmd.aggregate) return aggregate(spec, cmd.options.quiet).failed ? kExitFailed : 0;
  create_output_folder(spec.out);
  install_stop_signal_handlers();
  const StudyMembers members = spec.study_members();
  auto queue = make_local_queue(one_member(spec, cmd.member));
  if (!run_study_members(members, *queue, cmd.options)) return kExitStopped;
  return member_complete(members, std::size_t(cmd.member)) ? 0 : kExitFailed;
}

}  // namespace

int run_sweep_command(const SweepCommand& c) {
  SweepCommand cmd = c;
  if (cmd.options.jobs < 0) throw InputError("--jobs: must be >= 1");
  if (int(cmd.list) + int(cmd.member >= 0) + int(cmd.aggregate) > 1)
    throw InputError("sweep: --list, --member and --aggregate exclude each other");
  if (cmd.options.binary.empty()) cmd.options.binary = fs::read_symlink("/proc/self/exe");
  const SweepSpec spec = load_sweep_spec(cmd.study, cmd.sets, cmd.out);
  if (cmd.list || cmd.aggregate || cmd.member >= 0) {
    // One process's work: under mpirun only rank 0 does it (with -np 2, both ranks ran the
    // same --member into one folder and one of them failed on the other's lock).
    if (!mpi_launched()) return one_process_command(cmd, spec);
    MpiSession mpi;
    return mpi.rank() == 0 ? one_process_command(cmd, spec) : 0;
  }
  create_output_folder(spec.out);
  install_stop_signal_handlers();
  const StudyMembers members = spec.study_members();
  if (!mpi_launched()) {
    if (!cmd.options.quiet) report_grids(spec);
    auto queue = make_local_queue(pending_members(members));
    const bool finished = run_study_members(members, *queue, cmd.options);
    const int rc = study_exit_code(spec, aggregate(spec, cmd.options.quiet));
    return finished ? rc : kExitStopped;
  }
  MpiSession mpi;
  cmd.options.label = "fretbem sweep[rank " + std::to_string(mpi.rank()) + "]";
  if (!cmd.options.quiet && mpi.rank() == 0) report_grids(spec);
  // Only rank 0 decides what is pending: the others must not race it reading status files.
  auto queue =
      make_mpi_queue(mpi, mpi.rank() == 0 ? pending_members(members) : std::vector<std::size_t>{});
  const bool finished = run_study_members(members, *queue, cmd.options);
  mpi.barrier();
  const int rc = mpi.rank() == 0 ? study_exit_code(spec, aggregate(spec, cmd.options.quiet)) : 0;
  return finished ? rc : kExitStopped;
}

}  // namespace fretbem
