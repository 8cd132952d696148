// bench_robustness: a randomized sweep of cyclic cases through `fretbem run` (issue 18),
// recording per case the exit code, wall time, tangential iterations (sum and largest) and
// whether a solver fallback was announced. Any exit code other than 0 is a failure: every
// case is a load a user can type and that the solver must handle.
//
//   bench_robustness [--cases N] [--seed S] [--quick] [--fretbem PATH] [--out DIR]
//
// Cases (fixed seed: case i draws from std::mt19937_64(seed + i), the same cases on the same
// standard library): spheres (R 5-20 mm, contact radius 1/4-2/5 of the domain) and rough
// surfaces (Hurst 0.3-0.9, rms slope 0.02-0.1), rigid or elastic indenters (E2/E1 0.1-10),
// mu 0.05-1, n 32-128, analogy or Cerruti coupling, direction 0 or 0-90 degrees, and paths:
// force-controlled sine up to 0.99 mu F_z, displacement-controlled sine up to 10x the
// full-sliding shift mu (E*/G*) delta, tables with an oscillating normal force (force or
// shift), and tables reversing the tangential load at every row; 2-256 steps per cycle.
// --quick: 40 cases with n <= 64 and at most 64 steps per cycle (the ctest subset; exit 1
// when any case fails). Results: DIR/robustness.csv, one row per case.
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "fretbem/contact/normal_solver.hpp"
#include "fretbem/core/csv_reader.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/scenario/scenario.hpp"

namespace fs = std::filesystem;
using namespace fretbem;

namespace {

struct Case {
  std::string name, scenario, table;  // scenario text; table CSV (empty: sine path)
  int n = 32, steps = 0;
};

struct Options {
  int cases = 300;
  unsigned seed = 20261123;
  bool quick = false;
  std::string fretbem = FRETBEM_BINARY;
  fs::path out = "robustness_out";
};

double uniform(std::mt19937_64& rng, double a, double b) {
  return std::uniform_real_distribution<double>(a, b)(rng);
}
template <class T>
T pick(std::mt19937_64& rng, const std::vector<T>& v) {
  return v[std::uniform_int_distribution<std::size_t>(0, v.size() - 1)(rng)];
}

// Indentation of the case's surface under F_z (in process: the full-sliding shift of a rough
// surface has no closed form).
double indentation(const std::string& text, double Fz) {
  const Scenario sc = parse_scenario(text, "robustness", ".");
  HalfSpace hs(sc.grid, sc.material, Coupling::analogy);
  NormalSolver ns(hs);
  Field p;
  return ns.solve_force(make_surface(sc), Fz, p).indentation;
}

Case make_case(int i, const Options& o) {
  std::mt19937_64 rng(o.seed + unsigned(i));
  Case c;
  c.n = o.quick ? pick(rng, std::vector<int>{32, 48, 64})
                : pick(rng, std::vector<int>{32, 48, 64, 96, 128});
  const double mu = uniform(rng, 0.05, 1.0);
  const bool rough = uniform(rng, 0, 1) < 0.3;
  const bool elastic = uniform(rng, 0, 1) < 0.5;
  const bool cerruti = uniform(rng, 0, 1) < 0.4;
  const double direction = uniform(rng, 0, 1) < 0.6 ? 0.0 : uniform(rng, 0.0, 90.0);
  const double E = 210e9, nu = 0.3;
  const double E2 = elastic ? E * std::pow(10.0, uniform(rng, -1, 1)) : 0.0;
  const double nu2 = uniform(rng, 0.2, 0.45);
  std::ostringstream s;
  s << "[material]\nE = " << E << "\nnu = " << nu << "\nmu = " << mu << '\n';
  if (elastic) s << "E2 = " << E2 << "\nnu2 = " << nu2 << '\n';
  double Fz, length;
  std::string surface;
  if (rough) {
    length = 1e-3, Fz = uniform(rng, 50, 300);
    std::ostringstream r;
    r << "[surface]\ntype = rough\nhurst = " << uniform(rng, 0.3, 0.9)
      << "\nrms_slope = " << uniform(rng, 0.02, 0.1)
      << "\nseed = " << std::uniform_int_distribution<int>(1, 1000)(rng) << '\n';
    surface = r.str();
  } else {
    const double R = uniform(rng, 5e-3, 20e-3);
    Fz = uniform(rng, 5, 50);
    Material m;
    m.body1 = {E, nu};
    if (elastic) m.body2 = Body{E2, nu2};
    const double a = std::cbrt(3 * Fz * R / (4 * m.E_star()));
    length = 2 * a / uniform(rng, 0.5, 0.8);
    surface = "[surface]\ntype = sphere\nradius = " + std::to_string(R) + "\n";
  }
  s << "[grid]\nn = " << c.n << "\nlength = " << length << '\n' << surface;
  const std::string base = s.str();
  const int kind = std::uniform_int_distribution<int>(0, 4)(rng);
  // A sine needs 4 steps per cycle (its turning points); a table reversing at every row has
  // 2 rows per cycle.
  std::vector<int> spcs{2, 4, 8, 16, 32, 64, 128, 256};
  spcs.erase(spcs.begin() + (o.quick ? 6 : 8), spcs.end());
  if (kind <= 1) spcs.erase(spcs.begin());
  const int spc = pick(rng, spcs);
  const double force_amp = uniform(rng, 0.1, 0.99);
  Material m = parse_scenario(base + "[load]\nnormal_force = 1\n", "robustness", ".").material;
  const double ustar =
      mu * m.E_star() / m.G_star() * indentation(base + "[load]\nnormal_force = 1\n", Fz);
  const double disp_amp = ustar * std::pow(10.0, uniform(rng, -1, 1));
  std::ostringstream load;
  load << "[load]\ndirection = " << direction << '\n';
  std::ostringstream name;
  name << (rough ? "rough" : "sphere") << (elastic ? "/elastic" : "/rigid") << " n=" << c.n
       << " mu=" << mu << (cerruti ? " cerruti" : " analogy") << " dir=" << direction;
  if (kind <= 1) {  // sine, constant normal force
    load << "normal_force = " << Fz << "\npath = sine\ncycles = " << (o.quick ? 1 : 2)
         << "\nsteps_per_cycle = " << spc << '\n';
    if (kind == 0)
      load << "control = force\namplitude = " << force_amp << '\n',
          name << " sine force " << force_amp;
    else
      load << "control = displacement\ndisplacement_amplitude = " << disp_amp << '\n',
          name << " sine shift " << disp_amp / ustar << "U*";
    c.steps = spc * (o.quick ? 1 : 2);
  } else {  // tables: oscillating normal force; kind 4 reverses at every row
    const bool force = kind != 3;
    const int rows = kind == 4 ? spc : spc + 1;
    std::ostringstream t;
    t << "time,Fz," << (force ? "Fx" : "Ux") << '\n';
    for (int k = 0; k < rows; ++k) {
      const double ph = 2 * M_PI * k / spc;
      const double fz = Fz * (1 + 0.3 * std::sin(ph + 0.7));
      double q =
          kind == 4 ? (k == 0 ? 0.0 : (k % 2 ? 1 : -1) * uniform(rng, 0.2, 1.0)) : std::sin(ph);
      t << k << ',' << fz << ',' << (force ? q * force_amp * mu * fz : q * disp_amp) << '\n';
    }
    c.table = t.str();
    load << "path = table\ntable = table.csv\ncontrol = " << (force ? "force" : "displacement")
         << '\n';
    name << (kind == 4 ? " table reversing" : " table oscillating Fz")
         << (force ? " force" : " shift");
    c.steps = rows;
  }
  name << " steps=" << c.steps;
  c.scenario = base + load.str() +
               "[solver]\nstiffness = false\ncoupling = " + (cerruti ? "cerruti" : "analogy") +
               "\n[output]\nfields = none\n";
  c.name = name.str();
  return c;
}

struct Outcome {
  int exit = 0;
  double seconds = 0.0;
  long iterations = 0, max_iterations = 0;
  bool fallback = false;
};

Outcome run_case(const Case& c, int i, const Options& o) {
  const fs::path dir = o.out / ("case_" + std::to_string(i));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::string text = c.scenario;
  if (!c.table.empty()) std::ofstream(dir / "table.csv") << c.table;  // next to case.ini
  std::ofstream(dir / "case.ini") << text;
  const std::string cmd = "'" + o.fretbem + "' run '" + (dir / "case.ini").string() + "' --out '" +
                          (dir / "run").string() + "' --quiet > '" + (dir / "stdout.txt").string() +
                          "' 2> '" + (dir / "stderr.txt").string() + "'";
  Outcome r;
  const auto t0 = bench::Clock::now();
  const int status = std::system(cmd.c_str());
  r.seconds = bench::seconds_since(t0);
  r.exit = WIFEXITED(status) ? WEXITSTATUS(status) : 128;
  std::ifstream err(dir / "stderr.txt");
  std::string line;
  while (std::getline(err, line)) r.fallback |= line.find("fretbem: note:") != std::string::npos;
  const fs::path ts = dir / "run" / "timeseries.csv";
  if (!fs::exists(ts)) return r;
  csv::ReadOptions opt;
  opt.allow_nan = true;  // kx is nan with the stiffness solve off
  const csv::Table t = csv::read_table(ts, opt);
  const long col = t.find("tangential_iterations");
  for (const auto& row : t.rows) {
    const long it = col >= 0 ? std::lround(row[std::size_t(col)]) : 0;
    r.iterations += it, r.max_iterations = std::max(r.max_iterations, it);
  }
  return r;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    auto next = [&] { return k + 1 < argc ? std::string(argv[++k]) : std::string(); };
    if (a == "--quick")
      o.quick = true, o.cases = 40;
    else if (a == "--cases")
      o.cases = std::stoi(next());
    else if (a == "--seed")
      o.seed = unsigned(std::stoul(next()));
    else if (a == "--fretbem")
      o.fretbem = next();
    else if (a == "--out")
      o.out = next();
    else {
      std::fprintf(stderr, "bench_robustness: unknown option %s\n", a.c_str());
      std::exit(2);
    }
  }
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  fs::create_directories(o.out);
  std::ofstream csv(o.out / "robustness.csv");
  csv << "case,exit,seconds,tangential_iterations,max_tangential_iterations,fallback,steps,"
         "description\n";
  int failures = 0, fallbacks = 0;
  double total = 0.0;
  for (int i = 0; i < o.cases; ++i) {
    const Case c = make_case(i, o);
    const Outcome r = run_case(c, i, o);
    failures += r.exit != 0, fallbacks += r.fallback, total += r.seconds;
    csv << i << ',' << r.exit << ',' << r.seconds << ',' << r.iterations << ',' << r.max_iterations
        << ',' << r.fallback << ',' << c.steps << ",\"" << c.name << "\"\n";
    csv.flush();
    if (r.exit != 0 || r.fallback)
      std::printf("case %d: exit %d%s (%s), see %s\n", i, r.exit, r.fallback ? ", fallback" : "",
                  c.name.c_str(), (o.out / ("case_" + std::to_string(i))).string().c_str());
    else
      fs::remove_all(o.out / ("case_" + std::to_string(i)));
  }
  std::printf("bench_robustness: %d cases, %d failures, %d with a fallback, %.1f s\n", o.cases,
              failures, fallbacks, total);
  return failures ? 1 : 0;
}
