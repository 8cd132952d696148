// Time per load cycle of the Mindlin–Deresiewicz fretting loop (issue 4 "Speed"): Hertz
// sphere, contact radius L/4, force control +-0.6 mu F_z, 64 steps per cycle, at n = 128, 256,
// 512. Reports the median wall time of a steady cycle, the convolutions it used, and that time
// in units of one bare convolution measured in the same run (machine-independent).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "fretbem/history/model.hpp"
#include "fretbem/history/stepper.hpp"

using namespace fretbem;
using Clock = std::chrono::steady_clock;

namespace {

std::string scenario(int n, bool stiffness) {
  return "[material]\nE = 1\nnu = 0.3\nmu = 0.5\n[grid]\nn = " + std::to_string(n) +
         "\nlength = 1\n[surface]\ntype = sphere\nradius = 1\n[load]\nnormal_force = " +
         std::to_string(4.0 / 3.0 / 0.91 * 0.25 * 0.25 * 0.25) +
         "\npath = sine\ncontrol = force\namplitude = 0.6\ncycles = 2\nsteps_per_cycle = 64\n"
         "[solver]\nthreads = 1\nstiffness = " + (stiffness ? "true" : "false") + "\n";
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

struct CycleCost {
  double seconds;
  long convolutions;
};

// Runs the first cycle (transient), then times the second one.
CycleCost steady_cycle(int n, bool stiffness) {
  auto model = build_model(parse_scenario(scenario(n, stiffness), "bench", "."));
  Stepper stepper(*model);
  std::size_t k = 0;
  for (; model->path.steps[k].time <= 1.0 + 1e-12; ++k) stepper.advance(k);
  const auto c0 = model->half_space->convolutions();
  const auto t0 = Clock::now();
  for (; k < stepper.steps(); ++k) stepper.advance(k);
  return {std::chrono::duration<double>(Clock::now() - t0).count(),
          long(model->half_space->convolutions() - c0)};
}

double bare_convolution(int n) {
  Grid g = Grid::square(n, 1.0);
  Material m;
  m.body1 = {1.0, 0.3};
  HalfSpace hs(g, m, Coupling::analogy);
  Field p = Field::Random(n, n), u;
  std::vector<double> t;
  for (int r = 0; r < 21; ++r) {
    const auto t0 = Clock::now();
    hs.normal(p, u);
    t.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
  }
  return median(t);
}

}  // namespace

int main(int argc, char** argv) {
  const int max_n = argc > 1 ? std::atoi(argv[1]) : 512;
  const int repeats = argc > 2 ? std::atoi(argv[2]) : 3;
  std::printf("| n | stiffness | cycle (s) | convolutions / cycle | conv (ms) | cycle / conv |\n");
  std::printf("|---|---|---|---|---|---|\n");
  for (int n = 128; n <= max_n; n *= 2) {
    for (bool stiff : {true, false}) {
      std::vector<double> t;
      long conv = 0;
      for (int r = 0; r < repeats; ++r) {
        const CycleCost c = steady_cycle(n, stiff);
        t.push_back(c.seconds), conv = c.convolutions;
      }
      const double tc = bare_convolution(n), tm = median(t);
      std::printf("| %d | %s | %.3f | %ld | %.3f | %.0f |\n", n, stiff ? "on" : "off", tm, conv,
                  1e3 * tc, tm / tc);
      std::fflush(stdout);
    }
  }
}
