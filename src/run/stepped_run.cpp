#include "fretbem/run/stepped_run.hpp"

#include <cstdint>
#include <cstdio>
#include <string>

#include "fretbem/core/format.hpp"
#include "fretbem/core/stop_signal.hpp"
#include "fretbem/io/checkpoint.hpp"
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

// Stopped before the path's end: the checkpoint, the XDMF sidecar of what result.h5 holds, and
// the line that says how to continue.
int stop(Model& model, const Stepper& stepper, const ResultFile& h5) {
  const auto& dir = model.scenario.output.dir;
  save_checkpoint(dir, model, stepper);
  h5.write_xdmf();
  // Steps count rows of timeseries.csv: row 0 is the normal loading (as `check` counts).
  const std::string where =
      std::to_string(stepper.next_step()) + " of " + std::to_string(stepper.steps()) + " steps";
  return report_stop(where, dir);
}

}  // namespace

int run_steps(Model& model, Stepper& stepper, long resume_rows, const RunOptions& options) {
  const auto& dir = model.scenario.output.dir;
  TimeseriesCsv csv(dir, resume_rows);
  ResultFile h5(dir, model, resume_rows);
  // cycles.csv is written whole: a resumed run rebuilds its rows from the time series (below),
  // under today's header.
  CycleSummary cycles(dir, model.scenario.load.path, model.scenario.grid.h);
  Checkpointer checkpoint(dir, stepper, model.scenario.output.checkpoint_every);
  ProgressLine progress(model);
  ResolutionReport resolution;
  // A resumed run's cycle rows and resolution measures start from the rows already written.
  if (resume_rows > 0)
    for (const auto& r : read_timeseries(dir, std::size_t(resume_rows)))
      for (Observer* o : {static_cast<Observer*>(&cycles), static_cast<Observer*>(&resolution)})
        o->on_step(r, stepper.state(), model);
  std::vector<Observer*> obs{&csv, &h5, &cycles, &checkpoint, &resolution};
  if (!options.quiet) obs.push_back(&progress);
  const std::size_t budget = options.stop_after > 0 ? std::size_t(options.stop_after) : SIZE_MAX;
  // Step 0 (the normal loading) runs even when a stop was requested before it: a checkpoint
  // without it holds no step to resume after (next_step = 0 is refused).
  stepper.run(obs, budget, [&stepper] { return stepper.next_step() > 0 && stop_requested(); });
  if (stepper.next_step() < stepper.steps()) return stop(model, stepper, h5);
  const PathType path = model.scenario.load.path;
  print_summary(stepper.steps(), path == PathType::sine || path == PathType::table, csv.path(),
                dir / "cycles.csv", h5.path());
  if (!resolution.summary().empty()) std::printf("  %s\n", resolution.summary().c_str());
  for (const auto& w : resolution.warnings()) std::fprintf(stderr, "fretbem: %s\n", w.c_str());
  return 0;
}

}  // namespace fretbem
