// Benchmark of the incremental tangential solvers, with machine-independent cost.
//
// Cases, on a unit domain (E = 1, nu = 0.3, mu = 0.5, free boundary, analogy coupling):
//   cattaneo: Hertz sphere R = 1, contact radius L/4 (indentation 1/16), force-controlled ramp
//             q = F_x / (mu F_z) = 0.1 ... 0.9 in 9 increments;
//   rough:    Fourier-filtered rough surface (H = 0.5, rms slope 0.1, seed 42) pressed to a
//             contact fraction of ~5-10 %, displacement-controlled ramp U = 0.1 ... 0.9 U_slide,
//             U_slide = mu (E*/G*) delta the shift of full sliding (Ciavarella–Jäger, eq. 19).
// Both algorithms (ProjectedCgSolver, PartitionSolver); warm start (each increment from the
// previous step's state) and cold start (each load reached by one increment from the virgin
// state, zero traction). Every increment is solved to the tolerance (default 1e-10).
//
// Per row: mean iterations and FFT convolutions per increment, median (over repeats) wall and
// process-CPU time per increment, CPU time per iteration, and that over the CPU time of one
// bare convolution of the same padded size measured in the same run. CPU time is the robust
// figure on a shared machine: wall time includes waiting for other processes. Then the ratio of
// convolutions per increment partition / projected. Prints Markdown.
//
// Usage: bench_tangential [--max-n N] [--min-n N] [--repeats R] [--threads T] [--tol X]
//                         [--case cattaneo|rough|both] [--algorithm projected|partition|both]
//                         [--precondition off|on|auto|compare] [--rough-contact F]
// --precondition sets the projected solver's TangentialOptions::precondition; `compare` runs
// the projected solver both without and with it (rows "projected" and "projected+PCG").
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <map>
#include <memory>
#include <string>

#include "bench_util.hpp"
#include "fretbem/contact/normal_solver.hpp"
#include "fretbem/contact/tangential_solver.hpp"
#include "fretbem/surface/surface.hpp"

using namespace fretbem;
using bench::Clock;

namespace {

struct Options {
  int min_n = 128, max_n = 512, repeats = 3, threads = 1;
  double tol = 1e-10, rough_contact = 0.07;
  std::string cases = "both", algorithms = "both", precondition = "off";
};

void usage(int status) {
  bench::exit_with_usage(
      status,
      "usage: bench_tangential [--min-n N] [--max-n N] [--repeats R] [--threads T] "
      "[--tol X] [--case cattaneo|rough|both] [--algorithm projected|partition|both] "
      "[--precondition off|on|auto|compare] [--rough-contact F]\n");
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--max-n")
      o.max_n = bench::int_arg(argc, argv, i, 8, 1 << 14, usage);
    else if (a == "--min-n")
      o.min_n = bench::int_arg(argc, argv, i, 8, 1 << 14, usage);
    else if (a == "--repeats")
      o.repeats = bench::int_arg(argc, argv, i, 1, 1000, usage);
    else if (a == "--threads")
      o.threads = bench::int_arg(argc, argv, i, 1, 256, usage);
    else if (a == "--tol" && i + 1 < argc)
      o.tol = std::atof(argv[++i]);
    else if (a == "--case" && i + 1 < argc)
      o.cases = argv[++i];
    else if (a == "--rough-contact" && i + 1 < argc)
      o.rough_contact = std::atof(argv[++i]);
    else if (a == "--algorithm" && i + 1 < argc)
      o.algorithms = argv[++i];
    else if (a == "--precondition" && i + 1 < argc)
      o.precondition = argv[++i];
    else if (a == "--help" || a == "-h")
      usage(0);
    else
      usage(2);
  }
  return o;
}

/// A contact problem at fixed normal load and its tangential load sequence (absolute targets:
/// total force for force control, total shift for displacement control).
struct Case {
  std::string name;
  Grid grid;
  Material mat;
  std::unique_ptr<HalfSpace> hs;
  Field bound;
  TangentialControl control = TangentialControl::force;
  std::vector<double> targets;
  double contact_fraction = 0.0;
  int normal_iterations = 0, normal_convolutions = 0;
};

Material bench_material() {
  Material m;
  m.body1 = {1.0, 0.3};
  m.mu = 0.5;
  return m;
}

void set_normal(Case& c, const NormalResult& r, const Field& p) {
  c.bound = c.mat.mu * p;
  c.contact_fraction = double((p > 0).count()) / double(c.grid.size());
  c.normal_iterations = r.iterations;
  c.normal_convolutions = r.convolutions;
}

std::unique_ptr<Case> cattaneo(int n, const Options& o) {
  auto c = std::make_unique<Case>();
  c->name = "cattaneo";
  c->grid = Grid::square(n, 1.0);
  c->mat = bench_material();
  c->hs = std::make_unique<HalfSpace>(c->grid, c->mat, Coupling::analogy, FftOptions{o.threads});
  NormalSolver ns(*c->hs, {std::min(o.tol, 1e-10), 5000});
  Field p;
  const auto r = ns.solve_indentation(sphere_surface(c->grid, 1.0), 0.0625, p);  // a = L/4
  set_normal(*c, r, p);
  c->control = TangentialControl::force;
  for (int k = 1; k <= 9; ++k) c->targets.push_back(0.1 * k * c->mat.mu * r.force);
  return c;
}

std::unique_ptr<Case> rough(int n, const Options& o) {
  auto c = std::make_unique<Case>();
  c->name = "rough";
  c->grid = Grid::square(n, 1.0);
  c->mat = bench_material();
  c->hs = std::make_unique<HalfSpace>(c->grid, c->mat, Coupling::analogy, FftOptions{o.threads});
  RoughSpec spec;
  spec.hurst = 0.5;
  spec.rms_slope = 0.1;
  spec.method = RoughMethod::fourier;
  spec.seed = 42;
  const Field z = rough_surface(c->grid, spec);
  // Mean pressure for ~7 % contact (--rough-contact): A/A0 ~ kappa pbar / (E* slope) with
  // kappa ~ 2 (Persson; Hyun et al. 2004); the measured fraction is printed.
  const double pbar = o.rough_contact * c->mat.E_star() * 0.1 / 2.0;
  NormalSolver ns(*c->hs, {std::min(o.tol, 1e-10), 5000});
  Field p;
  const auto r = ns.solve_force(z, pbar * c->grid.length_x() * c->grid.length_y(), p);
  set_normal(*c, r, p);
  c->control = TangentialControl::displacement;
  const double slide = c->mat.mu * c->hs->tangential_ratio() * r.indentation;
  for (int k = 1; k <= 9; ++k) c->targets.push_back(0.1 * k * slide);
  return c;
}

struct Run {
  std::vector<int> iterations, convolutions;
  std::vector<double> seconds, cpu;  // wall and process CPU time per increment
};

/// One pass over the load sequence. Warm: increment k starts from the state of k-1. Cold:
/// increment k starts from zero traction and goes to the absolute target k in one step.
/// A solver variant: the algorithm and, for the projected CG, its preconditioning.
struct Variant {
  std::string label;
  bool partition = false;
  Precondition precondition = Precondition::off;
};

Run run_once(Case& c, const Variant& v, bool warm, double tol) {
  TangentialOperator op(*c.hs, Vec2(1, 0));
  std::unique_ptr<TangentialSolver> s;
  const TangentialOptions opt{tol, 100000, v.precondition};
  if (v.partition)
    s = std::make_unique<PartitionSolver>(op, opt);
  else
    s = std::make_unique<ProjectedCgSolver>(op, opt);
  // The displacement scale |C g| is computed once per bound and cached: do it before timing.
  {
    VecField t = op.zeros(), u = op.zeros();
    const VecField t0 = t, u0 = u;
    TangentialIncrement inc{&c.bound, &t0, &u0, TangentialControl::displacement,
                            Eigen::VectorXd::Zero(1)};
    s->solve(inc, t, u);
  }
  Run run;
  VecField tau = op.zeros(), u = op.zeros();
  double done = 0.0;
  for (const double target : c.targets) {
    if (!warm) tau = op.zeros(), u = op.zeros(), done = 0.0;
    const VecField tau0 = tau, u0 = u;
    const double step = c.control == TangentialControl::force ? target : target - done;
    TangentialIncrement inc{&c.bound, &tau0, &u0, c.control, Eigen::VectorXd::Constant(1, step)};
    const auto t0 = Clock::now();
    const std::clock_t c0 = std::clock();
    const TangentialResult r = s->solve(inc, tau, u);
    run.cpu.push_back(double(std::clock() - c0) / CLOCKS_PER_SEC);
    run.seconds.push_back(bench::seconds_since(t0));
    run.iterations.push_back(r.iterations);
    run.convolutions.push_back(r.convolutions);
    done = target;
  }
  return run;
}

struct Row {
  std::string name, algorithm, start;
  int n = 0;
  double fraction = 0, iterations = 0, convolutions = 0, seconds = 0, cpu = 0, conv_seconds = 0;
  int max_iterations = 0;
};

Row measure(Case& c, const Variant& v, bool warm, const Options& o, double conv_seconds) {
  std::vector<Run> runs;
  for (int r = 0; r < o.repeats; ++r) runs.push_back(run_once(c, v, warm, o.tol));
  Row row{c.name, v.label, warm ? "warm" : "cold", c.grid.nx, c.contact_fraction};
  const std::size_t inc = c.targets.size();
  for (std::size_t k = 0; k < inc; ++k) {
    std::vector<double> t, tc;
    for (const Run& r : runs) t.push_back(r.seconds[k]), tc.push_back(r.cpu[k]);
    row.seconds += bench::median(t) / inc;
    row.cpu += bench::median(tc) / inc;
    row.iterations += double(runs[0].iterations[k]) / inc;
    row.convolutions += double(runs[0].convolutions[k]) / inc;
    row.max_iterations = std::max(row.max_iterations, runs[0].iterations[k]);
  }
  row.conv_seconds = conv_seconds;
  return row;
}

std::vector<Variant> variants(const Options& o) {
  std::vector<Variant> v;
  if (o.algorithms != "partition") {
    if (o.precondition == "compare") {
      v.push_back({"projected", false, Precondition::off});
      v.push_back({"projected+PCG", false, Precondition::on});
    } else if (o.precondition == "on") {
      v.push_back({"projected+PCG", false, Precondition::on});
    } else if (o.precondition == "auto") {
      v.push_back({"projected (auto)", false, Precondition::automatic});
    } else {
      v.push_back({"projected", false, Precondition::off});
    }
  }
  if (o.algorithms != "projected") v.push_back({"partition", true, Precondition::off});
  return v;
}

const Row* find(const std::vector<Row>& rows, const Row& like, const std::string& algorithm,
                const std::string& start) {
  for (const Row& r : rows)
    if (r.name == like.name && r.n == like.n && r.algorithm == algorithm && r.start == start)
      return &r;
  return nullptr;
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  const double load0 = bench::load_average();
  std::vector<Row> rows;
  std::map<std::string, double> normal_info;
  for (int n = o.min_n; n <= o.max_n; n *= 2) {
    for (const std::string name : {"cattaneo", "rough"}) {
      if (o.cases != "both" && o.cases != name) continue;
      std::fprintf(stderr, "%s n = %d ...\n", name.c_str(), n);
      auto c = name == "cattaneo" ? cattaneo(n, o) : rough(n, o);
      Field f = c->grid.zeros(), u;
      const double conv = bench::cpu_per_call([&] { c->hs->normal(f, u); }, 5);
      std::fprintf(stderr,
                   "  contact %.2f %%, largest patch %lld nodes, normal solve %d iterations %d "
                   "convolutions\n",
                   100 * c->contact_fraction, (long long)largest_contact_patch(c->bound),
                   c->normal_iterations, c->normal_convolutions);
      for (const Variant& v : variants(o))
        for (bool warm : {true, false}) {
          rows.push_back(measure(*c, v, warm, o, conv));
          const Row& r = rows.back();
          std::fprintf(stderr, "  %s %s: %.1f it, %.1f conv, %.2f CPU ms per increment\n",
                       r.algorithm.c_str(), r.start.c_str(), r.iterations, r.convolutions,
                       1e3 * r.cpu);
        }
    }
  }
  std::printf(
      "Tangential increments, tolerance %.0e, FFTW threads %d, median of %d repeats; load "
      "average %.1f at start, %.1f at end (2 cores).\n\n",
      o.tol, o.threads, o.repeats, load0, bench::load_average());
  std::printf(
      "| case | n | contact | algorithm | start | iterations / inc. | max it. | convolutions / "
      "inc. | wall ms / inc. | CPU ms / inc. | CPU ms / iteration | iteration / conv. (CPU) "
      "|\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows) {
    const double per_it = r.cpu / std::max(1.0, r.iterations);
    std::printf("| %s | %d | %.1f %% | %s | %s | %.1f | %d | %.1f | %.1f | %.1f | %.3f | %.2f |\n",
                r.name.c_str(), r.n, 100 * r.fraction, r.algorithm.c_str(), r.start.c_str(),
                r.iterations, r.max_iterations, r.convolutions, 1e3 * r.seconds, 1e3 * r.cpu,
                1e3 * per_it, per_it / r.conv_seconds);
  }
  // Other variants against the plain projected CG, same case and start (same run).
  std::printf(
      "\nCPU time and convolutions per increment relative to the plain projected CG (same "
      "run):\n\n| case | n | algorithm | start | convolution ratio | CPU time ratio |\n"
      "|---|---|---|---|---|---|\n");
  for (const Row& r : rows) {
    const Row* base = find(rows, r, "projected", r.start);
    if (!base || base == &r) continue;
    std::printf("| %s | %d | %s | %s | %.2f | %.2f |\n", r.name.c_str(), r.n, r.algorithm.c_str(),
                r.start.c_str(), r.convolutions / base->convolutions, r.cpu / base->cpu);
  }
  return 0;
}
