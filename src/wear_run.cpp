// `fretbem run` for scenarios with a wear law: the wear outputs around integrate_wear.
#include <chrono>
#include <cstdio>

#include "fretbem/io/csv_writer.hpp"
#include "fretbem/run_output.hpp"
#include "fretbem/wear_integrator.hpp"

namespace fretbem {

namespace {

const std::vector<std::string>& wear_columns() {
  static const std::vector<std::string> c{
      "simulated_cycles", "N",          "energy_per_cycle", "wear_volume", "max_worn_depth",
      "contact_radius",   "stick_area", "peak_pressure",    "delta",       "max_slip"};
  return c;
}

// DIR/wear.csv (one row per simulated cycle), wear snapshots in result.h5, a progress line.
class WearFiles final : public WearLog {
 public:
  WearFiles(const std::filesystem::path& dir, ResultFile& h5, double N_end, bool quiet)
      : csv_(dir, "wear", wear_columns()), h5_(h5), N_end_(N_end), quiet_(quiet) {}
  void cycle(const WearCycle& c, double simulated) override {
    csv_.row({simulated, c.N, c.energy, c.wear_volume, c.max_depth, c.contact_radius, c.stick_area,
              c.peak_pressure, c.delta, c.max_slip});
    progress(c.N, simulated);
  }
  void snapshot(double N, const Field& worn, const Field& p) override {
    h5_.writer().write_step_fields(snapshots_++, N, {{"worn_depth", worn}, {"pressure", p}},
                                   "/wear/snapshot_");
  }
  void done() {
    if (shown_) std::fprintf(stderr, "\n");
  }

 private:
  void progress(double N, double simulated) {
    using namespace std::chrono;
    const auto now = steady_clock::now();
    if (quiet_ || duration<double>(now - last_).count() < 0.5) return;
    last_ = now, shown_ = true;
    std::fprintf(stderr, "\rwear: N %.6g / %.6g  simulated cycles %g   ", N, N_end_, simulated);
  }
  io::CsvWriter csv_;
  ResultFile& h5_;
  double N_end_;
  bool quiet_, shown_ = false;
  std::int64_t snapshots_ = 0;
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace

WearReport run_wear(Model& model, bool quiet) {
  const auto& dir = model.scenario.output.dir;
  Stepper stepper(model);
  TimeseriesCsv csv(dir);
  ResultFile h5(dir, model);
  CycleSummary cycles(dir);
  WearFiles log(dir, h5, model.scenario.wear.cycles, quiet);
  WearCycles sim(model, stepper, {&csv, &h5, &cycles});
  WearReport rep = integrate_wear(model, sim, &log);
  log.done();
  cycles.on_finish(stepper.state(), model);
  h5.on_finish(stepper.state(), model);
  h5.writer().write_field("/wear/final_worn_depth", rep.worn);
  if (!quiet && rep.newton_iterations > 0)
    std::printf(
        "fretbem: implicit wear steps: %ld Newton iterations (%ld convergence failures), %ld "
        "Krylov iterations, %ld inner CG iterations\n",
        rep.newton_iterations, rep.newton_failures, rep.krylov_iterations, rep.inner_iterations);
  if (!quiet)
    std::printf(
        "fretbem: wear to N = %.6g with %.6g simulated cycles (%d wear-map evaluations, "
        "%ld %s integrator steps, %ld rejected)\n  wear:        %s\n  time series: %s\n"
        "  fields:      %s\n",
        rep.N, rep.simulated_cycles, rep.rhs_evaluations, rep.steps,
        model.scenario.wear.integrator == WearIntegrator::cycle ? "cycle"
        : rep.implicit                                          ? "implicit (SDIRK)"
                                                                : "explicit (ERK)",
        rep.rejected, (dir / "wear.csv").string().c_str(), csv.path().string().c_str(),
        h5.path().string().c_str());
  return rep;
}

}  // namespace fretbem
