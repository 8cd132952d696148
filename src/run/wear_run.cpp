#include "fretbem/run/wear_run.hpp"

#include <cstdio>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/format.hpp"
#include "fretbem/io/checkpoint.hpp"
#include "fretbem/io/run_output.hpp"
#include "fretbem/io/wear_files.hpp"
#include "fretbem/run/stop_report.hpp"

namespace fretbem {

namespace {

// The last state (its cycle's last row), and the surfaces of the two bodies: the indenter's
// height, and the half-space's surface height against its unworn plane (negative where
// worn). The contact saw their difference.
void write_final_state(ResultFile& h5, const Model& model, const Stepper& stepper,
                       const Field& worn) {
  h5.save_fields(stepper.state(), model);
  h5.on_finish(stepper.state(), model);
  h5.writer().write_field("/surface/final", model.surface0 - indenter_worn(model, worn));
  h5.writer().write_field("/surface/final_half_space", -half_space_worn(model, worn));
  h5.writer().write_field("/wear/final_worn_depth", worn);
  h5.writer().write_field("/wear/final_worn_depth_indenter", indenter_worn(model, worn));
  h5.writer().write_field("/wear/final_worn_depth_half_space", half_space_worn(model, worn));
}

// The summary is printed with --quiet too: it silences progress, not results.
void print_summary(const Model& model, const WearReport& rep, const WearFiles& log,
                   const TimeseriesCsv& csv, const ResultFile& h5) {
  const double V = rep.worn.sum() * model.scenario.grid.cell_area();
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

}  // namespace

WearReport run_wear(Model& model, bool quiet, const Checkpoint* resume, long max_steps) {
  const auto& dir = model.scenario.output.dir;
  const WearCheckpoint* at = nullptr;
  Stepper stepper(model);
  if (resume) {
    if (!resume->wear)
      throw InputError((dir / "checkpoint.h5").string() + ": not a checkpoint of a wear run");
    at = &*resume->wear;
    model.surface = resume->surface;
    stepper.restore(resume->state, resume->memory);
  }
  const long rows = at ? long(at->counters.rows) : -1;
  TimeseriesCsv csv(dir, rows);
  ResultFile h5(dir, model, rows);
  WearFiles log(model, stepper, h5, quiet, at);
  WearCycles sim(model, stepper, {&csv, &h5});
  WearReport rep = integrate_wear(model, sim, log, at, max_steps);
  log.done();
  if (rep.stopped) {
    rep.exit_code = report_stop("N = " + simulated_count(rep.N) + " of " +
                                    format_count(model.scenario.wear.cycles) + " cycles",
                                dir);
    return rep;
  }
  write_final_state(h5, model, stepper, rep.worn);
  if (!quiet && rep.newton_iterations > 0)
    std::printf(
        "fretbem: implicit wear steps: %ld Newton iterations (%ld convergence failures), %ld "
        "Krylov iterations, %ld inner CG iterations\n",
        rep.newton_iterations, rep.newton_failures, rep.krylov_iterations, rep.inner_iterations);
  print_summary(model, rep, log, csv, h5);
  return rep;
}

}  // namespace fretbem
