// Extra cost of solver.coupling = coupled on a fretting cycle: Hertz sphere
// (contact radius L/4, rigid on E = 1, nu = 0.3: beta = 0.286), force control +-0.6 mu F_z,
// stiffness off, one thread. For cerruti and coupled: per step of a steady (second) cycle the
// convolutions (HalfSpace counter), the normal/tangential alternations, the CPU time, and the
// CPU time in units of one bare convolution of the same size measured in the same run
// (machine-independent on a loaded machine).
//
// Usage: bench_coupling [--n N] [--steps S] (defaults 128, 32 steps per cycle)
#include <cstdio>
#include <ctime>
#include <string>

#include "bench_util.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/history/stepper.hpp"

using namespace fretbem;

namespace {

int n = 128, steps = 32;

std::string scenario(const char* coupling) {
  return "[material]\nE = 1\nnu = 0.3\nmu = 0.5\n[grid]\nn = " + std::to_string(n) +
         "\nlength = 1\n[surface]\ntype = sphere\nradius = 1\n[load]\nnormal_force = " +
         std::to_string(4.0 / 3.0 / 0.91 * 0.25 * 0.25 * 0.25) +
         "\npath = sine\ncontrol = force\namplitude = 0.6\ncycles = 2\nsteps_per_cycle = " +
         std::to_string(steps) +
         "\n[solver]\nthreads = 1\nstiffness = none\ncoupling = " + coupling + "\n";
}

struct Cost {
  double cpu = 0;
  long convolutions = 0, alternations = 0, steps = 0;
};

// Runs the first cycle, then measures the second.
Cost steady_cycle(const char* coupling) {
  auto model = build_model(parse_scenario(scenario(coupling), "bench", "."));
  Stepper stepper(*model);
  std::size_t k = 0;
  for (; model->path.steps[k].time <= 1.0 + 1e-12; ++k) stepper.advance(k);
  Cost c;
  const auto c0 = model->half_space->convolutions();
  const std::clock_t t0 = std::clock();
  for (; k < stepper.steps(); ++k, ++c.steps)
    c.alternations += stepper.advance(k).coupling_iterations;
  c.cpu = double(std::clock() - t0) / CLOCKS_PER_SEC;
  c.convolutions = long(model->half_space->convolutions() - c0);
  return c;
}

double bare_convolution() {
  Grid g = Grid::square(n, 1.0);
  Material m;
  m.body1 = {1.0, 0.3};
  HalfSpace hs(g, m, Coupling::analogy, FftOptions{1, false, FftPrecision::float64});
  Field p = Field::Random(n, n), u;
  return bench::cpu_per_call([&] { hs.normal(p, u); }, 7);
}

void usage(int code) {
  bench::exit_with_usage(code, "usage: bench_coupling [--n N] [--steps S]\n");
}

}  // namespace

int main(int argc, char** argv) {
  bench::parse_int_options(argc, argv, {{"--n", &n, 8, 4096}, {"--steps", &steps, 4, 4096}}, usage);
  std::printf("load average %.2f at start; n = %d, %d steps per cycle\n\n", bench::load_average(),
              n, steps);
  std::printf(
      "| coupling | CPU / step (s) | convolutions / step | alternations / step | "
      "CPU / step in bare convolutions |\n|---|---|---|---|---|\n");
  const double tc = bare_convolution();
  Cost base;
  for (const char* coupling : {"cerruti", "coupled"}) {
    const Cost c = steady_cycle(coupling);
    const double s = double(c.steps);
    std::printf("| %s | %.3f | %.0f | %.2f | %.0f |\n", coupling, c.cpu / s, c.convolutions / s,
                c.alternations / s, c.cpu / s / tc);
    std::fflush(stdout);
    if (c.alternations == 0)
      base = c;
    else
      std::printf("\ncoupled / cerruti: CPU %.2fx, convolutions %.2fx\n", c.cpu / base.cpu,
                  double(c.convolutions) / double(base.convolutions));
  }
  std::printf("bare convolution %.3f ms CPU; load average %.2f at end\n", 1e3 * tc,
              bench::load_average());
}
