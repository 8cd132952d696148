// Run time against error: three cases with closed forms, swept over the
// grid n and the solver tolerance, run through the same Model/Stepper path as `fretbem run`.
//
// Sphere R = 1 on a unit domain, E = 1, nu = 0.3, mu = 0.5, Hertz contact radius a = L/4
// (delta = a^2 / R = 1/16), free boundary, analogy coupling, stiffness solve off (kx is not
// scored), one FFT thread.
//   hertz:    indentation delta; error |F / F_H(delta) - 1|, F_H = 4/3 E* R^1/2 delta^3/2
//             (Johnson eq. 4.22); second metric |A / (pi a^2) - 1|.
//   cattaneo: force ramp q = F_x / (mu P) = 0.1 ... 0.9 at P = F_H; error max_q of
//             |U_x / (u* (1 - (1-q)^(2/3))) - 1|, u* = mu delta E*/G* (Johnson eq. 7.42 with
//             the analogy's E*/G*); second metric max_q |A_stick / A - (1-q)^(2/3)|.
//   mindlin:  sine +-0.6 mu P, 2 cycles of 16 steps (turning points hit); error
//             |W / W_MD - 1| of the energy dissipated in the second (steady) cycle,
//             W_MD = (24/5) mu P u* [1 - (1-q)^(5/3) - (5q/6)(1 + (1-q)^(2/3))] (Johnson
//             §7.5, Mindlin & Deresiewicz 1953); second metric: the loop area's error.
// Series: double FFTs at every tolerance; float FFTs (solver.fft_precision = float) at the
// tolerances they accept (>= kFloatFftMinTolerance), in the same run.
// Time: median over repeats of the wall (and CPU) time of Stepper::run, the model (kernels,
// plans, surface) built outside the timed region. Prints CSV on stdout:
//   case,n,tol,wall_s,cpu_s,iterations,convolutions,error,error2,fft
// Usage: bench_accuracy_vs_time [--min-n N] [--max-n N] [--repeats R] [--large-repeats R]
//                               [--case hertz|cattaneo|mindlin|all] [--fft double|float|both]
//                               [--tols T1,T2,...]
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "bench_util.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/history/stepper.hpp"

using namespace fretbem;

namespace {

struct Options {
  int min_n = 32, max_n = 512, repeats = 3, large_repeats = 1;
  std::string cases = "all";
  std::vector<double> tols{1e-4, 1e-6, 1e-8, 1e-10, 1e-12};
  std::vector<std::string> ffts{"double", "float"};
};

void usage(int status) {
  bench::exit_with_usage(
      status,
      "usage: bench_accuracy_vs_time [--min-n N] [--max-n N] [--repeats R] "
      "[--large-repeats R] [--case hertz|cattaneo|mindlin|all] "
      "[--fft double|float|both] [--tols T1,T2,...]\n"
      "  --large-repeats R   repeats for n >= 512 (default 1)\n"
      "  --fft P             FFT precision series (default both; float skips "
      "tolerances below its floor)\n"
      "  --tols LIST         solver tolerances (default 1e-4,1e-6,1e-8,1e-10,1e-12)\n");
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--min-n")
      o.min_n = bench::int_arg(argc, argv, i, 8, 1 << 14, usage);
    else if (a == "--max-n")
      o.max_n = bench::int_arg(argc, argv, i, 8, 1 << 14, usage);
    else if (a == "--repeats")
      o.repeats = bench::int_arg(argc, argv, i, 1, 1000, usage);
    else if (a == "--large-repeats")
      o.large_repeats = bench::int_arg(argc, argv, i, 1, 1000, usage);
    else if (a == "--case" && i + 1 < argc)
      o.cases = argv[++i];
    else if (a == "--fft" && i + 1 < argc) {
      const std::string f = argv[++i];
      if (f != "double" && f != "float" && f != "both") usage(2);
      o.ffts =
          f == "both" ? std::vector<std::string>{"double", "float"} : std::vector<std::string>{f};
    } else if (a == "--tols" && i + 1 < argc) {
      o.tols.clear();
      std::stringstream list(argv[++i]);
      for (std::string t; std::getline(list, t, ',');) {
        char* end = nullptr;
        const double v = std::strtod(t.c_str(), &end);
        if (end == t.c_str() || *end != '\0' || !(v > 0 && v < 1e-2)) usage(2);
        o.tols.push_back(v);
      }
      if (o.tols.empty()) usage(2);
    } else if (a == "--help" || a == "-h")
      usage(0);
    else
      usage(2);
  }
  return o;
}

constexpr double kE = 1.0, kNu = 0.3, kMu = 0.5, kR = 1.0, kDelta = 1.0 / 16, kQ = 0.6;

Material material() {
  Material m;
  m.body1 = {kE, kNu};
  m.mu = kMu;
  return m;
}
double hertz_force() {
  return 4.0 / 3.0 * material().E_star() * std::sqrt(kR) * std::pow(kDelta, 1.5);
}
double ustar() {
  const Material m = material();
  return kMu * kDelta * m.E_star() / m.G_star();
}

std::string scenario_text(const std::string& name, int n, double tol, const std::string& fft) {
  std::ostringstream s;
  s.precision(17);
  s << "[material]\nE = " << kE << "\nnu = " << kNu << "\nmu = " << kMu << "\n[grid]\nn = " << n
    << "\nlength = 1\n[surface]\ntype = sphere\nradius = " << kR << "\n[load]\n";
  if (name == "hertz")
    s << "indentation = " << kDelta << "\npath = none\n";
  else if (name == "cattaneo")
    s << "normal_force = " << hertz_force() << "\npath = ramp\namplitude = 0.9\nsteps = 9\n";
  else
    s << "normal_force = " << hertz_force() << "\npath = sine\namplitude = " << kQ
      << "\ncycles = 2\nsteps_per_cycle = 16\n";
  s << "[solver]\ntolerance = " << tol
    << "\nthreads = 1\nstiffness = false\nfft_precision = " << fft << "\n";
  return s.str();
}

struct Collect : Observer {
  std::vector<StepRecord> rows;
  void on_step(const StepRecord& r, const InterfaceState&, const Model&) override {
    rows.push_back(r);
  }
};

struct Errors {
  double error = 0, error2 = 0;
  long iterations = 0, convolutions = 0;
};

Errors score(const std::string& name, const std::vector<StepRecord>& rows) {
  Errors e;
  for (const auto& r : rows)
    e.iterations += r.normal_iterations + r.tangential_iterations, e.convolutions += r.convolutions;
  const double a = std::sqrt(kR * kDelta), P = hertz_force();
  if (name == "hertz") {
    e.error = std::abs(rows[0].Fz / P - 1);
    e.error2 = std::abs(rows[0].contact_area / (M_PI * a * a) - 1);
  } else if (name == "cattaneo") {
    for (std::size_t k = 1; k < rows.size(); ++k) {
      const double q = rows[k].Fx / (kMu * rows[k].Fz);
      const double f = std::pow(1 - q, 2.0 / 3);
      e.error = std::max(e.error, std::abs(rows[k].Ux / (ustar() * (1 - f)) - 1));
      e.error2 = std::max(e.error2, std::abs(rows[k].stick_area / rows[k].contact_area - f));
    }
  } else {
    const double q = kQ, f = std::pow(1 - q, 2.0 / 3);
    const double W =
        24.0 / 5 * kMu * P * ustar() * (1 - std::pow(1 - q, 5.0 / 3) - 5 * q / 6 * (1 + f));
    double nodal = 0, loop = 0;
    for (std::size_t k = 1; k < rows.size(); ++k) {
      if (!(rows[k].time > 1 + 1e-12)) continue;
      nodal += rows[k].dissipation - rows[k - 1].dissipation;
      loop += 0.5 * (rows[k].Fx + rows[k - 1].Fx) * (rows[k].Ux - rows[k - 1].Ux);
    }
    e.error = std::abs(nodal / W - 1);
    e.error2 = std::abs(loop / W - 1);
  }
  return e;
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  std::printf("# load average %.1f at start (2 cores)\n", bench::load_average());
  std::printf("case,n,tol,wall_s,cpu_s,iterations,convolutions,error,error2,fft\n");
  // (precision, tolerance) pairs; float skips the tolerances below its round-off floor, which
  // the scenario would refuse.
  std::vector<std::pair<std::string, double>> series;
  for (const std::string& fft : o.ffts)
    for (const double tol : o.tols)
      if (fft == "double" || tol >= kFloatFftMinTolerance) series.emplace_back(fft, tol);
  for (int n = o.min_n; n <= o.max_n; n *= 2) {
    for (const std::string name : {"hertz", "cattaneo", "mindlin"}) {
      if (o.cases != "all" && o.cases != name) continue;
      for (const auto& [fft, tol] : series) {
        std::vector<double> wall, cpu;
        Errors e;
        const int reps = n >= 512 ? o.large_repeats : o.repeats;
        for (int r = 0; r < reps; ++r) {
          const Scenario sc = parse_scenario(scenario_text(name, n, tol, fft), name,
                                             std::filesystem::temp_directory_path());
          auto model = build_model(sc);
          Stepper stepper(*model);
          Collect c;
          const auto t0 = bench::Clock::now();
          const std::clock_t c0 = std::clock();
          stepper.run({&c});
          cpu.push_back(double(std::clock() - c0) / CLOCKS_PER_SEC);
          wall.push_back(bench::seconds_since(t0));
          e = score(name, c.rows);
        }
        std::printf("%s,%d,%.0e,%.6g,%.6g,%ld,%ld,%.6e,%.6e,%s\n", name.c_str(), n, tol,
                    bench::median(wall), bench::median(cpu), e.iterations, e.convolutions, e.error,
                    e.error2, fft.c_str());
        std::fflush(stdout);
      }
    }
  }
  std::printf("# load average %.1f at end\n", bench::load_average());
  return 0;
}
