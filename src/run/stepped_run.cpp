#include "fretbem/run/stepped_run.hpp"

#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

#include "fretbem/core/format.hpp"
#include "fretbem/core/rank_zero.hpp"
#include "fretbem/core/stop_signal.hpp"
#include "fretbem/history/slab_state.hpp"
#include "fretbem/io/checkpoint.hpp"
#include "fretbem/io/gathered_writers.hpp"
#include "fretbem/io/resolution_report.hpp"
#include "fretbem/io/run_output.hpp"
#include "fretbem/io/run_tables.hpp"
#include "fretbem/run/stop_report.hpp"

namespace fretbem {

namespace {

// The final summary: printed with --quiet too (it silences progress, not results).
void print_summary(std::size_t steps, bool cyclic, const std::filesystem::path& ts,
                   const std::filesystem::path& cycles, const std::filesystem::path& h5) {
  std::printf("fretbem: %zu steps done\n", steps);
  if (const auto e = cyclic ? steady_energy(cycles) : std::nullopt)
    std::printf("  energy per cycle: %s J (cycle %d, the last complete one)\n",
                format_number(e->second).c_str(), e->first);
  std::printf("  time series: %s\n  cycles:      %s\n  fields:      %s\n", ts.string().c_str(),
              cycles.string().c_str(), h5.string().c_str());
}

// The observers that write the run's files and its terminal lines: on rank 0 only of a grid
// distributed over ranks (serial: the one process).
struct RunWriters {
  TimeseriesCsv csv;
  ResultFile h5;
  CycleSummary cycles;
  ProgressLine progress;
  ResolutionReport resolution;

  RunWriters(const Model& model, long resume_rows)
      : csv(model.scenario.output.dir, resume_rows),
        h5(model.scenario.output.dir, model, resume_rows),
        // Written whole: a resumed run rebuilds its rows from the time series, under today's
        // header.
        cycles(model.scenario.output.dir, model.scenario.load.path, model.scenario.grid.h),
        progress(model) {}
};

// Stopped before the path's end: the checkpoint, the XDMF sidecar of what result.h5 holds, and
// the line that says how to continue (rank 0's exit code on every rank).
int stop(Model& model, const Stepper& stepper, const RunWriters* files) {
  const auto& dir = model.scenario.output.dir;
  save_checkpoint(dir, model, stepper);
  // Steps count rows of timeseries.csv: row 0 is the normal loading (as `check` counts).
  const std::string where =
      std::to_string(stepper.next_step()) + " of " + std::to_string(stepper.steps()) + " steps";
  long code = 0;
  const Communicator& comm = model.half_space->communicator();
  const int sig = int(comm.max(double(stop_signal())));  // a signal may reach one rank only
  on_rank_zero(comm, [&] {
    files->h5.write_xdmf();
    code = report_stop(where, dir, sig);
  });
  return int(broadcast_count(comm, code));
}

void finish(const Model& model, const Stepper& stepper, const RunWriters& files) {
  const PathType path = model.scenario.load.path;
  print_summary(stepper.steps(), path == PathType::sine || path == PathType::table,
                files.csv.path(), model.scenario.output.dir / "cycles.csv", files.h5.path());
  const ResolutionReport& resolution = files.resolution;
  if (!resolution.summary().empty()) std::printf("  %s\n", resolution.summary().c_str());
  for (const auto& w : resolution.warnings()) std::fprintf(stderr, "fretbem: %s\n", w.c_str());
}

}  // namespace

int run_steps(Model& model, Stepper& stepper, long resume_rows, const RunOptions& options) {
  const auto& dir = model.scenario.output.dir;
  const Communicator& comm = model.half_space->communicator();
  // A resumed run's cycle rows and resolution measures start from the rows already written.
  const InterfaceState resumed =
      resume_rows > 0 ? gathered(*model.half_space, stepper.state()) : InterfaceState();
  std::unique_ptr<RunWriters> files;
  on_rank_zero(comm, [&] {
    files = std::make_unique<RunWriters>(model, resume_rows);
    if (resume_rows > 0)
      for (const auto& r : read_timeseries(dir, std::size_t(resume_rows)))
        for (Observer* o :
             {static_cast<Observer*>(&files->cycles), static_cast<Observer*>(&files->resolution)})
          o->on_step(r, resumed, model);
  });
  Checkpointer checkpoint(dir, stepper, model.scenario.output.checkpoint_every);
  std::vector<Observer*> writers;
  if (files) writers = {&files->csv, &files->h5, &files->cycles, &files->resolution};
  if (files && !options.quiet) writers.push_back(&files->progress);
  GatheredWriters gathered_writers(writers);
  std::vector<Observer*> obs{&gathered_writers, &checkpoint};
  if (!comm.distributed()) {  // the files before the checkpoint that refers to them
    obs = {writers[0], writers[1], writers[2], &checkpoint, writers[3]};
    if (!options.quiet) obs.push_back(&files->progress);
  }
  const std::size_t budget = options.stop_after > 0 ? std::size_t(options.stop_after) : SIZE_MAX;
  // Step 0 (the normal loading) runs even when a stop was requested before it: a checkpoint
  // without it holds no step to resume after (next_step = 0 is refused). A signal reaches the
  // ranks at different steps: the ranks stop when one has seen it.
  stepper.run(obs, budget, [&] { return stepper.next_step() > 0 && comm.any(stop_requested()); });
  if (stepper.next_step() < stepper.steps()) return stop(model, stepper, files.get());
  on_rank_zero(comm, [&] { finish(model, stepper, *files); });
  return 0;
}

}  // namespace fretbem
