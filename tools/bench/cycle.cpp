// Time per load cycle of the Mindlin–Deresiewicz fretting loop: Hertz
// sphere, contact radius L/4, force control +-0.6 mu F_z, 64 steps per cycle, at n = 128, 256,
// 512, with solver.stiffness = every, turning and none, and solver.predictor = none and cycle.
// Reports the median wall and process CPU time of the first cycle (virgin loading and two
// reversals: nothing to predict from, the Masing image warm-starts the reloading branch), the
// second (with the predictor also of the third: the second is the first it predicts, the
// Masing image starting its opening quarter), the convolutions it used, and the CPU time in units
// of one bare convolution of the same padded size measured in the same run (machine-independent),
// and per convolution the solvers performed (the overhead of their element-wise passes).
// FFT plans as `fretbem run` makes them (MEASURE with wisdom), one thread, and the allocator
// kept from returning freed memory to the kernel as `fretbem run` keeps it (keep_freed_memory).
//
// The unit (bare_convolution.hpp) is sampled before every timed cycle and after the last; each
// row uses the median of its own samples and reports their spread (min-max over median).
//
// Usage: bench_cycle [--max-n N] [--repeats R] [--min-n N] [--headline 1] [--cycles C]
// (--headline 1: only the headline configuration, stiffness = turning with the predictor;
// --cycles C: cycles of the rows with the predictor, 3 unless given, for profiling steady ones.)
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <string>
#include <utility>
#include <vector>

#include "bare_convolution.hpp"
#include "bench_util.hpp"
#include "fretbem/core/resources.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/history/stepper.hpp"

using namespace fretbem;

namespace {

std::string scenario(int n, const char* stiffness, const char* predictor, int cycles) {
  return "[material]\nE = 1\nnu = 0.3\nmu = 0.5\n[grid]\nn = " + std::to_string(n) +
         "\nlength = 1\n[surface]\ntype = sphere\nradius = 1\n[load]\nnormal_force = " +
         std::to_string(4.0 / 3.0 / 0.91 * 0.25 * 0.25 * 0.25) +
         "\npath = sine\ncontrol = force\namplitude = 0.6\ncycles = " + std::to_string(cycles) +
         "\nsteps_per_cycle = 64\n[solver]\nthreads = 1\nstiffness = " + stiffness +
         "\npredictor = " + predictor + "\n";
}

struct CycleCost {
  double wall, cpu;
  long convolutions;
};

// Times every cycle, the first one from step 0 (the initial normal loading and, with a
// stiffness solve, its k_x included); the unit is sampled before every cycle and after the
// last.
std::vector<CycleCost> all_cycles(int n, const char* stiffness, const char* predictor, int cycles,
                                  bench::BareConvolution& unit) {
  auto model = build_model(parse_scenario(scenario(n, stiffness, predictor, cycles), "bench", "."));
  Stepper stepper(*model);
  std::size_t k = 0;
  std::vector<CycleCost> out;
  for (int c = 1; c <= cycles; ++c) {
    unit.sample();
    const auto c0 = model->half_space->convolutions();
    const auto t0 = bench::Clock::now();
    const double cpu0 = bench::cpu_now();
    for (; k < stepper.steps() && model->path.steps[k].time <= c + 1e-12; ++k) stepper.advance(k);
    out.push_back({bench::seconds_since(t0), bench::cpu_now() - cpu0,
                   long(model->half_space->convolutions() - c0)});
  }
  unit.sample();
  return out;
}

int max_n = 512, min_n = 128, repeats = 3, headline = 0, predicted_cycles = 3;

void usage(int code) {
  bench::exit_with_usage(
      code,
      "usage: bench_cycle [--min-n N] [--max-n N] [--repeats R] [--headline 0|1] [--cycles C]\n");
}

}  // namespace

int main(int argc, char** argv) {
  keep_freed_memory();  // as fretbem's main: the cycles reuse freed grid-sized buffers
  bench::parse_int_options(argc, argv,
                           {{"--max-n", &max_n, 8, 4096},
                            {"--min-n", &min_n, 8, 4096},
                            {"--repeats", &repeats, 1, 100},
                            {"--headline", &headline, 0, 1},
                            {"--cycles", &predicted_cycles, 2, 1000}},
                           usage);
  std::printf("load average %.2f at start\n\n", bench::load_average());
  std::printf(
      "| n | stiffness | predictor | cycle | cycle wall (s) | cycle CPU (s) | convolutions / cycle "
      "| conv CPU (ms), median | conv spread (min-max / median) | cycle CPU / conv | CPU per "
      "solver convolution / conv |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (int n = min_n; n <= max_n; n *= 2) {
    bench::BareConvolution unit(n, true);
    std::vector<double> all;
    for (const char* predictor : {"none", "cycle"}) {
      if (headline && predictor[0] == 'n') continue;
      const int cycles = predictor[0] == 'n' ? 2 : predicted_cycles;
      for (const char* stiff : {"every", "turning", "none"}) {
        if (headline && stiff[0] != 't') continue;
        std::vector<std::vector<double>> wall(cycles), cpu(cycles);
        std::vector<long> conv(cycles);
        for (int r = 0; r < repeats; ++r) {
          const std::vector<CycleCost> cs = all_cycles(n, stiff, predictor, cycles, unit);
          for (std::size_t i = 0; i < cs.size(); ++i)
            wall[i].push_back(cs[i].wall), cpu[i].push_back(cs[i].cpu),
                conv[i] = cs[i].convolutions;
        }
        const std::vector<double> t = unit.take();
        all.insert(all.end(), t.begin(), t.end());
        const double tc = bench::median(t);
        const auto [lo, hi] = std::minmax_element(t.begin(), t.end());
        for (std::size_t i = 0; i < conv.size(); ++i) {
          const double tm = bench::median(cpu[i]);
          // Last column: what one convolution of the solvers costs with the element-wise passes
          // and sparse updates around it, in bare convolutions (1 = no overhead).
          std::printf(
              "| %d | %s | %s | %zu | %.3f | %.3f | %ld | %.3f | %.0f %% (%zu samples) | "
              "%.0f | %.2f |\n",
              n, stiff, predictor, i + 1, bench::median(wall[i]), tm, conv[i], 1e3 * tc,
              100.0 * (*hi - *lo) / tc, t.size(), tm / tc, tm / tc / double(conv[i]));
        }
        std::fflush(stdout);
      }
    }
    const auto [lo, hi] = std::minmax_element(all.begin(), all.end());
    std::printf(
        "n = %d: bare convolution over the whole run: median %.3f ms, min %.3f, max %.3f "
        "(%zu samples)\n",
        n, 1e3 * bench::median(all), 1e3 * *lo, 1e3 * *hi, all.size());
  }
  std::printf("\nload average %.2f at end\n", bench::load_average());
}
