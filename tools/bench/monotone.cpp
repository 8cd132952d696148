// End-to-end cost of the rough monotone run (target: the n = 512 run within
// 1160 bare-convolution equivalents): rough_monotone.ini's material and surface (midpoint
// fBm, rms slope 0.05, seed 1) at n = 512, H = 0.5, force control to 0.9 mu F_z in 9 increments,
// k_x every step, one thread. Timed from the model's construction (surface, plans, kernels) to
// the last step, process CPU; output files are not part of it (the run writes none at
// fields = none but its CSV rows). The unit (bare_convolution.hpp) is sampled before the run,
// after every step and after the run, with the plans the run uses; the ratio is the run's CPU
// over the median of its own samples.
//
// Usage: bench_monotone [--n N] [--repeats R] [--plan estimate|measure] [--hurst H]
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bare_convolution.hpp"
#include "bench_util.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/history/stepper.hpp"

using namespace fretbem;

namespace {

int n = 512, repeats = 3;
std::string plan = "estimate", hurst = "0.5";

std::string scenario() {
  return "[material]\nE = 210e9\nnu = 0.3\nmu = 0.5\n[grid]\nn = " + std::to_string(n) +
         "\nlength = 1e-3\n[surface]\ntype = rough\nmethod = midpoint\nhurst = " + hurst +
         "\nrms_slope = 0.05\nseed = 1\n[load]\nnormal_force = 300\npath = ramp\n"
         "control = force\namplitude = 0.9\nsteps = 9\n[solver]\ntolerance = 1e-6\n"
         "threads = 1\nstiffness = every\nfft_plan = " +
         plan + "\n";
}

struct RunCost {
  double cpu;
  long convolutions;
};

RunCost one_run(bench::BareConvolution& unit) {
  unit.sample();
  const double cpu0 = bench::cpu_now();
  double paused = 0.0;
  auto model = build_model(parse_scenario(scenario(), "bench", "."));
  Stepper stepper(*model);
  for (std::size_t k = 0; k < stepper.steps(); ++k) {
    stepper.advance(k);
    const double s0 = bench::cpu_now();
    unit.sample();
    paused += bench::cpu_now() - s0;
  }
  return {bench::cpu_now() - cpu0 - paused, long(model->half_space->convolutions())};
}

void usage(int code) {
  bench::exit_with_usage(code,
                         "usage: bench_monotone [--n N] [--repeats R] [--plan estimate|measure] "
                         "[--hurst H]\n");
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<char*> rest{argv[0]};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if ((a == "--plan" || a == "--hurst") && i + 1 < argc) {
      (a == "--plan" ? plan : hurst) = argv[++i];
      if (a == "--plan" && plan != "estimate" && plan != "measure") usage(2);
    } else {
      rest.push_back(argv[i]);
    }
  }
  bench::parse_int_options(int(rest.size()), rest.data(),
                           {{"--n", &n, 8, 4096}, {"--repeats", &repeats, 1, 100}}, usage);
  std::printf("load average %.2f at start; n = %d, H = %s, %s plans, one thread\n\n",
              bench::load_average(), n, hurst.c_str(), plan.c_str());
  std::printf(
      "| repeat | run CPU (s) | convolutions | conv CPU (ms), median | conv spread (min-max / "
      "median) | run CPU / conv | per solver convolution |\n|---|---|---|---|---|---|---|\n");
  bench::BareConvolution unit(n, plan == "measure");
  std::vector<double> ratios, cpus;
  for (int r = 0; r < repeats; ++r) {
    const RunCost c = one_run(unit);
    const std::vector<double> t = unit.take();
    const double tc = bench::median(t);
    const auto [lo, hi] = std::minmax_element(t.begin(), t.end());
    ratios.push_back(c.cpu / tc), cpus.push_back(c.cpu);
    std::printf("| %d | %.3f | %ld | %.3f | %.0f %% (%zu samples) | %.0f | %.2f |\n", r + 1, c.cpu,
                c.convolutions, 1e3 * tc, 100.0 * (*hi - *lo) / tc, t.size(), c.cpu / tc,
                c.cpu / tc / double(c.convolutions));
    std::fflush(stdout);
  }
  std::printf("\nmedian: run CPU %.3f s, %.0f bare-convolution equivalents\n", bench::median(cpus),
              bench::median(ratios));
  std::printf("load average %.2f at end\n", bench::load_average());
}
