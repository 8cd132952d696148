// Normal solver cost in machine-independent units and the Fourier preconditioner's
// effect: for a Hertz sphere (contact radius L/4) and a rough surface (H = 0.5, rms slope
// 0.1, seed 42, ~6 % contact) at n = 128 ... 1024, cold-started force-controlled solves to
// 1e-10 with plain Polonsky–Keer CG and with the preconditioned CG (M^-1 = S K^-1 S).
// Reports contact elements, iterations, convolutions, median CPU time, CPU time per iteration
// over the CPU time of one bare convolution (same run), and the time ratio preconditioned/plain.
//
// Usage: bench_normal_cost [--min-n N] [--max-n N] [--repeats R] [--large-repeats R]
#include <cmath>
#include <cstdio>
#include <ctime>
#include <string>

#include "bench_util.hpp"
#include "fretbem/contact/normal_solver.hpp"
#include "fretbem/surface/surface.hpp"

using namespace fretbem;

namespace {

struct Options {
  int min_n = 128, max_n = 1024, repeats = 3, large_repeats = 1;
};

void usage(int status) {
  bench::exit_with_usage(status,
                         "usage: bench_normal_cost [--min-n N] [--max-n N] [--repeats R] "
                         "[--large-repeats R (n >= 1024)]\n");
}

Options parse(int argc, char** argv) {
  Options o;
  bench::parse_grid_range(argc, argv, o.min_n, o.max_n, o.repeats,
                          {{"--large-repeats", &o.large_repeats, 1, 1000}}, usage);
  return o;
}

struct Result {
  long contact = 0;
  int iterations = 0, convolutions = 0;
  double cpu = 0;
};

Result solve(HalfSpace& hs, const Field& z, double force, bool pre, int repeats) {
  NormalSolver ns(hs, {1e-10, 20000, pre ? Precondition::on : Precondition::off});
  Result res;
  std::vector<double> t;
  for (int r = 0; r < repeats; ++r) {
    Field p;
    const std::clock_t c0 = std::clock();
    const NormalResult nr = ns.solve_force(z, force, p);
    t.push_back(double(std::clock() - c0) / CLOCKS_PER_SEC);
    res.contact = (p > 0).count();
    res.iterations = nr.iterations;
    res.convolutions = nr.convolutions;
  }
  res.cpu = bench::median(t);
  return res;
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  std::printf(
      "Normal solves, force control, tolerance 1e-10, cold start, 1 FFTW thread, median CPU "
      "time; load average %.1f at start (2 cores).\n\n",
      bench::load_average());
  std::printf(
      "| case | n | contact elements | PCG | iterations | convolutions | CPU s | CPU per "
      "iteration / conv. | time PCG / plain |\n|---|---|---|---|---|---|---|---|---|\n");
  for (int n = o.min_n; n <= o.max_n; n *= 2) {
    const int reps = n >= 1024 ? o.large_repeats : o.repeats;
    Material mat;
    mat.body1 = {1.0, 0.3};
    const Grid grid = Grid::square(n, 1.0);
    HalfSpace hs(grid, mat, Coupling::analogy, FftOptions{1});
    Field f = grid.zeros(), u;
    const double conv = bench::cpu_per_call([&] { hs.normal(f, u); }, 5);
    RoughSpec spec;
    spec.hurst = 0.5;
    spec.rms_slope = 0.1;
    spec.method = RoughMethod::fourier;
    spec.seed = 42;
    const double hertz = 4.0 / 3.0 * mat.E_star() * std::pow(0.25, 3);
    const double rough = 0.07 * mat.E_star() * 0.1 / 2.0;
    for (const std::string name : {"hertz", "rough"}) {
      const Field z = name == "hertz" ? sphere_surface(grid, 1.0) : rough_surface(grid, spec);
      const double F = name == "hertz" ? hertz : rough;
      std::fprintf(stderr, "%s n = %d ...\n", name.c_str(), n);
      Result plain;
      for (const bool pre : {false, true}) {
        const Result r = solve(hs, z, F, pre, reps);
        if (!pre) plain = r;
        std::printf("| %s | %d | %ld | %s | %d | %d | %.3f | %.2f | %s |\n", name.c_str(), n,
                    r.contact, pre ? "yes" : "no", r.iterations, r.convolutions, r.cpu,
                    r.cpu / std::max(1, r.iterations) / conv,
                    pre ? std::to_string(r.cpu / plain.cpu).substr(0, 4).c_str() : "1");
        std::fflush(stdout);
      }
    }
  }
  std::printf("\nload average %.1f at end\n", bench::load_average());
  return 0;
}
