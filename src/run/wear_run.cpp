#include "fretbem/run/wear_run.hpp"

#include <cstdio>
#include <memory>
#include <optional>
#include <vector>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/format.hpp"
#include "fretbem/core/rank_zero.hpp"
#include "fretbem/core/stop_signal.hpp"
#include "fretbem/history/slab_state.hpp"
#include "fretbem/io/checkpoint.hpp"
#include "fretbem/io/gathered_writers.hpp"
#include "fretbem/io/run_output.hpp"
#include "fretbem/io/wear_files.hpp"
#include "fretbem/run/stop_report.hpp"

namespace fretbem {

namespace {

// The last state (its cycle's last row), and the surfaces of the two bodies: the indenter's
// height, and the half-space's surface height against its unworn plane (negative where
// worn). The contact saw their difference. The whole grid's state and worn depth (rank 0).
void write_final_state(ResultFile& h5, const Model& model, const InterfaceState& state,
                       const Field& worn) {
  h5.save_fields(state, model);
  h5.on_finish(state, model);
  h5.writer().write_field("/surface/final", model.surface0 - indenter_worn(model, worn));
  h5.writer().write_field("/surface/final_half_space", -half_space_worn(model, worn));
  h5.writer().write_field("/wear/final_worn_depth", worn);
  h5.writer().write_field("/wear/final_worn_depth_indenter", indenter_worn(model, worn));
  h5.writer().write_field("/wear/final_worn_depth_half_space", half_space_worn(model, worn));
}

// The summary is printed with --quiet too: it silences progress, not results. V is the
// worn volume of the whole grid.
void print_summary(const Model& model, const WearReport& rep, double V, const WearFiles& log,
                   const TimeseriesCsv& csv, const ResultFile& h5) {
  const double s = model.scenario.wear.indenter_share;
  std::printf("fretbem: wear to N = %s with %s simulated cycles (%d wear-map evaluations",
              format_count(rep.N).c_str(), simulated_count(rep.simulated_cycles).c_str(),
              rep.rhs_evaluations);
  if (rep.cycle_by_cycle)
    std::printf(", cycle by cycle)\n");
  else
    std::printf(
        "; %ld %s steps, %ld error-test failures, %ld Newton failures; %ld stretches of %s "
        "cycles simulated one by one)\n",
        rep.steps, rep.implicit ? "implicit (TR-BDF2)" : "explicit (ERK)", rep.rejected,
        rep.newton_failures, rep.stretches, format_count(rep.stretch_cycles).c_str());
  std::printf("  worn volume: %.6g m^3 (indenter %.6g, half-space %.6g)\n", V, s * V,
              (1.0 - s) * V);
  if (const auto [N, energy] = log.last_accepted(); N >= 0.0)
    std::printf("  energy per cycle: %.6g J (at N = %s)\n", energy, format_count(N).c_str());
  std::printf("  cycles:      %s\n  time series: %s\n  fields:      %s\n",
              log.path().string().c_str(), csv.path().string().c_str(), h5.path().string().c_str());
}

// The files of a wear run besides cycles.csv, on rank 0 of a distributed grid.
struct WearRunFiles {
  TimeseriesCsv csv;
  ResultFile h5;
  WearRunFiles(const Model& model, long rows)
      : csv(model.scenario.output.dir, rows), h5(model.scenario.output.dir, model, rows) {}
};

// The end of a finished run on every rank: rank 0 writes the final fields (gathered) and
// prints the summary.
void finish(const Model& model, const Stepper& stepper, const WearReport& rep, bool quiet,
            WearRunFiles* files, const WearFiles& log) {
  const HalfSpace& hs = *model.half_space;
  const Communicator& comm = hs.communicator();
  const InterfaceState state = gathered(hs, stepper.state());
  const Field worn = gathered(hs, rep.worn);
  const double V = comm.sum(rep.worn.sum()) * model.scenario.grid.cell_area();
  on_rank_zero(comm, [&] {
    write_final_state(files->h5, model, state, worn);
    if (!quiet && rep.newton_iterations > 0)
      std::printf(
          "fretbem: implicit wear steps: %ld Newton iterations (%ld convergence failures), %ld "
          "Krylov iterations, %ld inner CG iterations\n",
          rep.newton_iterations, rep.newton_failures, rep.krylov_iterations, rep.inner_iterations);
    print_summary(model, rep, V, log, files->csv, files->h5);
  });
}

}  // namespace

// On a grid distributed over ranks every rank simulates its slab; rank 0 alone writes, from
// fields gathered to it (docs/mpi-grid.md), and its exit code is every rank's.
WearReport run_wear(Model& model, bool quiet, const Checkpoint* resume, long max_steps) {
  const auto& dir = model.scenario.output.dir;
  const HalfSpace& hs = *model.half_space;
  const Communicator& comm = hs.communicator();
  const WearCheckpoint* at = nullptr;
  std::optional<WearCheckpoint> at_slab;
  Stepper stepper(model);
  if (resume) {
    if (!resume->wear)
      throw InputError((dir / "checkpoint.h5").string() + ": not a checkpoint of a wear run");
    at_slab = *resume->wear;
    at_slab->worn = slab_of(hs, resume->wear->worn);
    at_slab->warm = resume->wear->warm.mapped([&](const Field& x) { return slab_of(hs, x); });
    at = &*at_slab;
    model.surface = resume->surface;
    stepper.restore(slab_of(hs, resume->state), slab_of(hs, resume->memory));
  }
  const long rows = at ? long(at->counters.rows) : -1;
  std::unique_ptr<WearRunFiles> files;
  on_rank_zero(comm, [&] { files = std::make_unique<WearRunFiles>(model, rows); });
  WearFiles log(model, stepper, files ? &files->h5 : nullptr, quiet, at);
  std::vector<Observer*> writers;
  if (files) writers = {&files->csv, &files->h5};
  GatheredWriters gathered_writers(writers);
  WearCycles sim(model, stepper,
                 comm.distributed() ? std::vector<Observer*>{&gathered_writers} : writers);
  WearReport rep = integrate_wear(model, sim, log, at, max_steps);
  log.done();
  if (rep.stopped) {
    long code = 0;
    const int sig = int(comm.max(double(stop_signal())));  // a signal may reach one rank only
    on_rank_zero(comm, [&] {
      code = report_stop("N = " + simulated_count(rep.N) + " of " +
                             format_count(model.scenario.wear.cycles) + " cycles",
                         dir, sig);
    });
    rep.exit_code = int(broadcast_count(comm, code));
    return rep;
  }
  finish(model, stepper, rep, quiet, files.get(), log);
  return rep;
}

}  // namespace fretbem
