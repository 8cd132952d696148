// `fretbem run` for scenarios with a wear law: the wear outputs and checkpoints around
// integrate_wear.
#include <chrono>
#include <cmath>
#include <cstdio>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/format.hpp"
#include "fretbem/core/stop_signal.hpp"
#include "fretbem/io/checkpoint.hpp"
#include "fretbem/io/csv_writer.hpp"
#include "fretbem/io/run_output.hpp"
#include "fretbem/wear/cost_estimate.hpp"
#include "fretbem/wear/integrator.hpp"

namespace fretbem {

namespace {

// Simulated cycles are sums of fractions of a period (a steady cycle counts 1.2 at one step
// per ramp step), and an ODE run's N is real: printed to 1e-6 cycles so round-off
// ("67.80000000000007", "N = 8801.740264644288") does not show; whole counts as integers.
std::string simulated_count(double simulated) {
  return format_count(std::round(simulated * 1e6) / 1e6);
}

// DIR/cycles.csv of a wear run: one row per simulated cycle, then the bookkeeping
// columns; the per-body volumes split wear_volume by wear.indenter_share.
const std::vector<std::string>& wear_columns() {
  static const std::vector<std::string> c{"N",
                                          "energy_per_cycle",
                                          "wear_volume",
                                          "max_worn_depth",
                                          "contact_radius",
                                          "stick_area",
                                          "peak_pressure",
                                          "delta",
                                          "max_slip",
                                          "simulated_cycles",
                                          "accepted",
                                          "wear_volume_indenter",
                                          "wear_volume_half_space"};
  return c;
}

// DIR/cycles.csv, wear snapshots in result.h5, DIR/checkpoint.h5, a progress line.
class WearFiles final : public WearLog {
 public:
  WearFiles(const Model& model, const Stepper& stepper, ResultFile& h5, bool quiet,
            const WearCheckpoint* resume)
      : model_(model),
        stepper_(stepper),
        csv_(open_csv(model.scenario.output.dir, "cycles", wear_columns(),
                      resume ? resume->cycles_rows : -1)),
        h5_(h5),
        progress_(!quiet) {
    if (resume) rows_ = resume->cycles_rows, snapshots_ = resume->snapshots;
  }
  bool stop_requested() const override { return fretbem::stop_requested(); }
  void cycle(const WearCycle& c) override {
    const double s = model_.scenario.wear.indenter_share;
    // N is the count a cycle stands for: integral in cycle mode and stretches (summed ones),
    // where round-off must not print 2.9999999999999996 (format_count).
    csv_.row({snap_count(c.N), c.energy, c.wear_volume, c.max_depth, c.contact_radius, c.stick_area,
              c.peak_pressure, c.delta, c.max_slip, c.simulated, c.accepted ? 1.0 : 0.0,
              s * c.wear_volume, (1.0 - s) * c.wear_volume});
    ++rows_;
    if (c.accepted) last_accepted_ = {snap_count(c.N), c.energy};
    progress(c.N, c.simulated);
  }
  // The total worn depth (what the gap sees) and each body's share of it; and, at the end of
  // a simulated cycle, the fields asked of that state.
  void snapshot(double N, const Field& worn, const Field& p, bool cycle_end) override {
    if (cycle_end) h5_.save_fields(stepper_.state(), model_);
    h5_.writer().write_step_fields(snapshots_++, N,
                                   {{"worn_depth", worn},
                                    {"worn_depth_indenter", indenter_worn(model_, worn)},
                                    {"worn_depth_half_space", half_space_worn(model_, worn)},
                                    {"pressure", p}},
                                   "/wear/snapshot_");
  }
  void step_done(const WearCheckpoint& at) override {
    WearCheckpoint c = at;
    c.cycles_rows = rows_, c.snapshots = snapshots_;
    save_checkpoint(model_.scenario.output.dir, model_, stepper_, &c);
  }
  void expect(double low, double high) override { expected_ = {low, high}; }
  // On stderr, with --quiet too: it says what the run will cost before it is spent.
  void warn(const std::string& line) override {
    progress_.finish();
    std::fprintf(stderr, "fretbem: %s\n", line.c_str());
  }
  void done() { progress_.finish(); }
  const std::filesystem::path& path() const { return csv_.path(); }
  /// N and energy_per_cycle (J) of the last accepted cycles.csv row (none yet: N < 0).
  std::pair<double, double> last_accepted() const { return last_accepted_; }

 private:
  // The ETA counts on the simulated cycles, which carry the cost (one steady cycle each), not
  // on N: an ODE integrator's steps lengthen with N, so N / wear.cycles overstates the time
  // left by orders of magnitude early on (fretting_wear.ini at n = 64: 83 s at 1 s for 3.4 s
  // left). The expected range's middle first, then its upper end, then N once the run exceeds
  // both (its cost is then unknown).
  double done_share(double N, double simulated) const {
    if (simulated < expected_.middle()) return simulated / expected_.middle();
    if (simulated < expected_.high) return simulated / expected_.high;
    return N / model_.scenario.wear.cycles;
  }
  void progress(double N, double simulated) {
    const double total = model_.scenario.wear.cycles;
    progress_.update("wear: N " + format_count(N) + " / " + format_count(total) +
                         "  simulated cycles " + simulated_count(simulated),
                     done_share(N, simulated));
  }
  const Model& model_;
  const Stepper& stepper_;
  io::CsvWriter csv_;
  ResultFile& h5_;
  ProgressReporter progress_;
  long rows_ = 0;
  std::int64_t snapshots_ = 0;
  std::pair<double, double> last_accepted_{-1.0, 0.0};
  SimulatedCycles expected_;  // none yet (a resumed ODE run): the ETA counts on N
};

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
  WearReport rep = integrate_wear(model, sim, &log, at, max_steps);
  log.done();
  if (rep.stopped) {
    rep.exit_code = report_stop("N = " + simulated_count(rep.N) + " of " +
                                    format_count(model.scenario.wear.cycles) + " cycles",
                                dir);
    return rep;
  }
  h5.save_fields(stepper.state(), model);  // the last state (its cycle's last row)
  h5.on_finish(stepper.state(), model);
  // The surfaces of the two bodies: the indenter's height, and the half-space's surface
  // height against its unworn plane (negative where worn). The contact saw their difference.
  h5.writer().write_field("/surface/final", model.surface0 - indenter_worn(model, rep.worn));
  h5.writer().write_field("/surface/final_half_space", -half_space_worn(model, rep.worn));
  h5.writer().write_field("/wear/final_worn_depth", rep.worn);
  h5.writer().write_field("/wear/final_worn_depth_indenter", indenter_worn(model, rep.worn));
  h5.writer().write_field("/wear/final_worn_depth_half_space", half_space_worn(model, rep.worn));
  if (!quiet && rep.newton_iterations > 0)
    std::printf(
        "fretbem: implicit wear steps: %ld Newton iterations (%ld convergence failures), %ld "
        "Krylov iterations, %ld inner CG iterations\n",
        rep.newton_iterations, rep.newton_failures, rep.krylov_iterations, rep.inner_iterations);
  // The summary is printed with --quiet too: it silences progress, not results.
  {
    const double V = rep.worn.sum() * model.scenario.grid.cell_area();
    const double s = model.scenario.wear.indenter_share;
    const bool cycles = rep.cycle_by_cycle;
    std::printf("fretbem: wear to N = %s with %s simulated cycles (%d wear-map evaluations",
                format_count(rep.N).c_str(), simulated_count(rep.simulated_cycles).c_str(),
                rep.rhs_evaluations);
    if (cycles)
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
                log.path().string().c_str(), csv.path().string().c_str(),
                h5.path().string().c_str());
  }
  return rep;
}

}  // namespace fretbem
