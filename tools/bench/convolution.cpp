// Benchmark of the half-space operator and the normal solver.
//
// For each n: median time of one bare convolution (HalfSpace::normal) with FFTW_ESTIMATE and
// FFTW_MEASURE plans, median time of a full Hertz normal solve (force control, tolerance 1e-10,
// contact diameter half the domain), its iterations and convolutions, the time per CG iteration
// over the bare convolution time of the same plan, and the number of nodes at which
// normal_add_sparse costs as much as one convolution (the solvers switch at
// HalfSpace::sparse_limit() = max(24, n/2)). Prints a Markdown table.
//
// Usage: bench_convolution [--max-n N] [--repeats R] [--threads T] [--no-measure]
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "fretbem/elastic/grid.hpp"
#include "fretbem/elastic/half_space.hpp"
#include "fretbem/elastic/material.hpp"
#include "fretbem/contact/normal_solver.hpp"
#include "fretbem/surface/surface.hpp"

using namespace fretbem;
using bench::Clock;
using bench::median;
using bench::seconds_since;
using bench::time_per_call;

namespace {

struct Options {
  int max_n = 1024;
  int repeats = 5;
  int threads = 1;
  bool measure = true;
};

[[noreturn]] void usage(const char* argv0, int status) {
  std::fprintf(status ? stderr : stdout,
               "usage: %s [--max-n N] [--repeats R] [--threads T] [--no-measure]\n"
               "  --max-n N      largest grid (128, 256, 512, 1024; default 1024)\n"
               "  --repeats R    timing repeats, median reported (default 5)\n"
               "  --threads T    FFTW threads (default 1)\n"
               "  --no-measure   skip the FFTW_MEASURE plans (slow to build at large n)\n",
               argv0);
  std::exit(status);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> int {
      if (i + 1 >= argc) usage(argv[0], 2);
      char* end = nullptr;
      const long v = std::strtol(argv[++i], &end, 10);
      if (*end != '\0' || v < 1 || v > 1 << 20) usage(argv[0], 2);
      return int(v);
    };
    if (a == "--max-n")
      o.max_n = value();
    else if (a == "--repeats")
      o.repeats = value();
    else if (a == "--threads")
      o.threads = value();
    else if (a == "--no-measure")
      o.measure = false;
    else if (a == "--help" || a == "-h")
      usage(argv[0], 0);
    else
      usage(argv[0], 2);
  }
  return o;
}

struct Row {
  int n = 0;
  double conv_est = 0, conv_meas = 0, plan_meas = 0;
  double solve = 0;
  int iterations = 0, convolutions = 0;
  double per_iteration = 0, ratio = 0;
  double sparse_node = 0, break_even = 0;
};

Row run(int n, const Options& opt) {
  Row row;
  row.n = n;
  Material mat;
  mat.body1 = Body{210e9, 0.3};
  const double L = 1e-3, R = 0.05, a = L / 4;  // Hertz contact diameter = L/2, as the tests
  const Grid grid = Grid::square(n, L);
  const Field z = sphere_surface(grid, R);
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  Field p(grid.nx, grid.ny), u;
  for (Eigen::Index k = 0; k < p.size(); ++k) p(k) = u01(rng);

  HalfSpace hs(grid, mat, Coupling::analogy, FftOptions{opt.threads, false});
  if (opt.measure) {
    const auto t0 = Clock::now();
    HalfSpace hm(grid, mat, Coupling::analogy, FftOptions{opt.threads, true});
    row.plan_meas = seconds_since(t0);
    row.conv_meas = time_per_call([&] { hm.normal(p, u); }, opt.repeats);
  }

  // The bare convolution, the sparse update and the full solve are timed back to back in each
  // repeat, and the ratios formed per repeat: on a shared machine the load changes between
  // repeats, and a ratio of two times taken seconds apart would mix two loads.
  const double force = 4 * mat.E_star() * a * a * a / (3 * R);
  NormalSolver solver(hs);   // default options: tolerance 1e-10
  constexpr int nodes = 16;  // sparse update: cost per node from a batch of 16 random nodes
  std::vector<std::int64_t> idx(nodes);
  std::vector<double> val(nodes, 1.0);
  std::uniform_int_distribution<std::int64_t> pick(0, std::int64_t(grid.size()) - 1);
  for (auto& i : idx) i = pick(rng);
  Field us = grid.zeros();
  std::vector<double> conv, solve, sparse, ratio, even;
  for (int r = 0; r < opt.repeats; ++r) {
    conv.push_back(time_per_call([&] { hs.normal(p, u); }, 1));
    sparse.push_back(time_per_call([&] { hs.normal_add_sparse(idx, val, us); }, 1) / nodes);
    Field q;
    const auto t0 = Clock::now();
    const NormalResult res = solver.solve_force(z, force, q);  // cold start
    solve.push_back(seconds_since(t0));
    row.iterations = res.iterations;
    row.convolutions = res.convolutions;
    ratio.push_back(solve.back() / std::max(1, res.iterations) / conv.back());
    even.push_back(conv.back() / sparse.back());
  }
  row.conv_est = median(conv);
  row.solve = median(solve);
  row.per_iteration = row.solve / std::max(1, row.iterations);
  row.ratio = median(ratio);
  row.sparse_node = median(sparse);
  row.break_even = median(even);
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  const Options opt = parse(argc, argv);
  std::vector<Row> rows;
  for (int n : {128, 256, 512, 1024}) {
    if (n > opt.max_n) break;
    std::fprintf(stderr, "n = %d ...\n", n);
    rows.push_back(run(n, opt));
  }
  std::printf(
      "FFTW threads: %d; median of %d repeats (ratios formed within each repeat); Hertz "
      "solve: force control, tolerance 1e-10, ESTIMATE plans, cold start.\n\n",
      opt.threads, opt.repeats);
  std::printf(
      "| n | padded | conv ESTIMATE (ms) | conv MEASURE (ms) | MEASURE plan (s) | solve (ms) | "
      "iterations | convolutions | per iteration (ms) | iteration / conv | sparse per node "
      "(us) | sparse break-even (nodes) |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows) {
    std::printf("| %d | %d² | %.3f | ", r.n, 2 * r.n, 1e3 * r.conv_est);
    if (opt.measure)
      std::printf("%.3f | %.2f | ", 1e3 * r.conv_meas, r.plan_meas);
    else
      std::printf("– | – | ");
    std::printf("%.1f | %d | %d | %.3f | %.2f | %.2f | %.0f |\n", 1e3 * r.solve, r.iterations,
                r.convolutions, 1e3 * r.per_iteration, r.ratio, 1e6 * r.sparse_node, r.break_even);
  }
  return 0;
}
