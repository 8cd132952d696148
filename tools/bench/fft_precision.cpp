// Float against double FFT convolutions (float FFTs as an opt-in Pareto point):
// for each n, the CPU time of one bare convolution (HalfSpace::normal) in both precisions,
// timed back to back in every repeat and the ratio formed per repeat; the float result's
// relative error against the double one; and, up to --max-solve-n, what it does to a Hertz
// normal solve.
//
// Grid: L = 1 mm, steel (E = 210 GPa, nu = 0.3), sphere R = 50 mm, Hertz contact radius L/4,
// free boundary, ESTIMATE plans, one FFT thread. Loads: the Hertz pressure (smooth, one sign)
// and uniform random numbers in [0, 1) (every wavenumber). Errors: ||u_f - u_d||_2 / ||u_d||_2
// over the grid, and max |u_f - u_d| / max |u_d|.
// Solves (force control, cold start): reference double at 1e-10; double and float at 1e-6;
// relative error of the indentation delta and of the pressure (L2) against the reference.
//
// Usage: bench_fft_precision [--max-n N] [--max-solve-n N] [--repeats R]
#include <cmath>
#include <cstdio>
#include <ctime>
#include <random>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "fretbem/contact/normal_solver.hpp"
#include "fretbem/elastic/grid.hpp"
#include "fretbem/elastic/half_space.hpp"
#include "fretbem/elastic/material.hpp"
#include "fretbem/surface/surface.hpp"

using namespace fretbem;

namespace {

struct Options {
  int max_n = 1024, max_solve_n = 512, repeats = 5;
};

void usage(int status) {
  bench::exit_with_usage(status,
                         "usage: bench_fft_precision [--max-n N] [--max-solve-n N] [--repeats R]\n"
                         "  --max-n N        largest grid of the convolution table (default 1024)\n"
                         "  --max-solve-n N  largest grid of the Hertz solve table (default 512)\n"
                         "  --repeats R      timing repeats, median reported (default 5)\n");
}

Options parse(int argc, char** argv) {
  Options o;
  bench::parse_int_options(argc, argv,
                           {{"--max-n", &o.max_n, 8, 1 << 14},
                            {"--max-solve-n", &o.max_solve_n, 0, 1 << 14},
                            {"--repeats", &o.repeats, 1, 1000}},
                           usage);
  return o;
}

constexpr double kL = 1e-3, kR = 0.05, kA = kL / 4;

Material steel() {
  Material m;
  m.body1 = Body{210e9, 0.3};
  return m;
}

double rel_l2(const Field& a, const Field& ref) {
  return std::sqrt((a - ref).square().sum() / ref.square().sum());
}
double rel_max(const Field& a, const Field& ref) {
  return (a - ref).abs().maxCoeff() / ref.abs().maxCoeff();
}

void convolution_row(int n, const Options& o) {
  const Grid grid = Grid::square(n, kL);
  HalfSpace hd(grid, steel(), Coupling::analogy, FftOptions{1, false, FftPrecision::float64});
  HalfSpace hf(grid, steel(), Coupling::analogy, FftOptions{1, false, FftPrecision::float32});
  Field hertz = grid.zeros(), noise(grid.nx, grid.ny);
  for (int j = 0; j < grid.ny; ++j)
    for (int i = 0; i < grid.nx; ++i) {
      const double r2 = grid.x(i) * grid.x(i) + grid.y(j) * grid.y(j);  // centred
      hertz(i, j) = r2 < kA * kA ? std::sqrt(1 - r2 / (kA * kA)) : 0.0;
    }
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  for (Eigen::Index k = 0; k < noise.size(); ++k) noise(k) = u01(rng);
  Field ud, uf;
  std::vector<double> td, tf, ratio;
  for (int r = 0; r < o.repeats; ++r) {
    td.push_back(bench::cpu_per_call([&] { hd.normal(noise, ud); }, 1));
    tf.push_back(bench::cpu_per_call([&] { hf.normal(noise, uf); }, 1));
    ratio.push_back(tf.back() / td.back());
  }
  hd.normal(noise, ud);
  hf.normal(noise, uf);
  const double noise_l2 = rel_l2(uf, ud), noise_max = rel_max(uf, ud);
  hd.normal(hertz, ud);
  hf.normal(hertz, uf);
  std::printf("| %d | %d² | %.3f | %.3f | %.2f | %.2e | %.2e | %.2e | %.2e |\n", n, 2 * n,
              1e3 * bench::median(td), 1e3 * bench::median(tf), bench::median(ratio),
              rel_l2(uf, ud), rel_max(uf, ud), noise_l2, noise_max);
  std::fflush(stdout);
}

struct Solve {
  NormalResult res;
  Field p;
  double cpu = 0.0;
};

Solve solve(const Grid& grid, const Field& z, FftPrecision prec, double tol) {
  HalfSpace hs(grid, steel(), Coupling::analogy, FftOptions{1, false, prec});
  NormalSolver solver(hs, NormalOptions{tol, 2000});
  const double force = 4 * steel().E_star() * kA * kA * kA / (3 * kR);
  Solve s;
  const std::clock_t c0 = std::clock();
  s.res = solver.solve_force(z, force, s.p);
  s.cpu = double(std::clock() - c0) / CLOCKS_PER_SEC;
  return s;
}

void solve_rows(int n) {
  const Grid grid = Grid::square(n, kL);
  const Field z = sphere_surface(grid, kR);
  const Solve ref = solve(grid, z, FftPrecision::float64, 1e-10);
  for (const FftPrecision prec : {FftPrecision::float64, FftPrecision::float32}) {
    const Solve s = solve(grid, z, prec, 1e-6);
    std::printf("| %d | %s | 1e-6 | %d | %.3g | %.3f | %.2e | %.2e |\n", n,
                prec == FftPrecision::float32 ? "float" : "double", s.res.iterations,
                s.res.residual, s.cpu, std::abs(s.res.indentation / ref.res.indentation - 1),
                rel_l2(s.p, ref.p));
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  std::printf(
      "load average %.1f at start (2 cores); one FFT thread, ESTIMATE plans, CPU time, "
      "median of %d repeats (ratio per repeat)\n\n",
      bench::load_average(), o.repeats);
  std::printf(
      "| n | padded | conv double (ms) | conv float (ms) | float / double | error Hertz L2 | "
      "error Hertz max | error random L2 | error random max |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  for (int n = 128; n <= o.max_n; n *= 2) convolution_row(n, o);
  if (o.max_solve_n >= 128) {
    std::printf(
        "\nHertz normal solve, force control, cold start; errors against double at 1e-10\n\n");
    std::printf(
        "| n | FFT | tolerance | iterations | residual | CPU s | delta error | pressure "
        "error L2 |\n");
    std::printf("|---|---|---|---|---|---|---|---|\n");
    for (int n = 128; n <= o.max_solve_n; n *= 2) solve_rows(n);
  }
  std::printf("\nload average %.1f at end\n", bench::load_average());
  return 0;
}
