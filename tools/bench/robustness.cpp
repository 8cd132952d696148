// bench_robustness: a randomized sweep of cyclic cases through `fretbem run`,
// recording per case the exit code, wall time, tangential iterations (sum and largest) and
// whether a solver fallback was announced. Any exit code other than 0 is a failure: every
// case is a load a user can type and that the solver must handle.
//
//   bench_robustness [--cases N] [--first K] [--seed S] [--quick] [--list] [--fretbem PATH]
//                    [--out DIR]
//
// Cases (fixed seed: case i draws from std::mt19937_64(seed + i), the same cases on the same
// standard library; --first K runs cases K .. K+N-1, so a long sweep runs in chunks): spheres
// (R 5-20 mm, contact radius 1/4-2/5 of the domain), rough surfaces (Hurst 0.3-0.9, rms
// slope 0.01-0.2, log-uniform) and flat punches as wide as the domain; rigid or elastic
// indenters (E2/E1 0.1-10); nu and nu2 0-0.5; mu 0.05-1.5; n 32-128, free or periodic grids;
// analogy or Cerruti coupling; projected or partition algorithm; constant, static_kinetic or
// evolving (dissipation or slip path) friction; and paths: sine or ramp at constant normal
// force (any direction), tables with an oscillating normal force, tables reversing at every
// row, triangles, 2-D ellipses (Fx, Fy or Ux, Uy) and a normal force down to 1e-6-1e-2 of
// its peak and back; force amplitudes 1e-3-0.99 of the lowest mu F_z the friction law reaches,
// shift amplitudes 1e-3-10x the full-sliding shift mu (E*/G*) delta (both log-uniform); 2-256
// steps per cycle. --quick: 40 cases with n <= 64 and at most 64 steps per cycle (the ctest
// subset; exit 1 when any case fails). --list prints the cases without running them.
// Results: DIR/robustness.csv, one row per case (wall and CPU time of the run).
#include <sys/resource.h>
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
  int cases = 300, first = 0;  // cases first .. first + cases - 1
  unsigned seed = 20261123;
  bool quick = false, list = false;  // list: print the cases, run nothing
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

// Coefficient bounds of the case's friction law (material.mu = mu): force amplitudes are
// relative to mu F_z and must stay below the lowest coefficient the law can reach.
struct Law {
  std::string name, text;  // law and its [friction] section (empty: constant)
  double lowest = 1;       // lowest coefficient / mu
};

Law friction_law(std::mt19937_64& rng, double mu, double ustar, double traction) {
  Law l;
  const double u = uniform(rng, 0, 1);
  std::ostringstream f;
  if (u < 0.15) {
    const double k = uniform(rng, 0.5, 1.0);
    l.name = " static_kinetic";
    f << "[friction]\nlaw = static_kinetic\nmu_kinetic = " << k * mu << '\n';
    l.lowest = k;
  } else if (u < 0.3) {
    const double k = uniform(rng, 0.5, 1.5);
    const bool slip = uniform(rng, 0, 1) < 0.5;
    // Scales of one cycle: the slip path ~ U*, the dissipated energy density ~ mu p U*.
    const double scale = (slip ? ustar : traction * ustar) * std::pow(10.0, uniform(rng, -1, 1));
    l.name = slip ? " evolving(slip)" : " evolving(energy)";
    f << "[friction]\nlaw = evolving\nmu_final = " << k * mu
      << "\nevolution = " << (slip ? "slip_path" : "dissipation") << "\nscale = " << scale << '\n';
    l.lowest = std::min(1.0, k);
  }
  l.text = f.str();
  return l;
}

// Over 80 lines on purpose: every value of a case is drawn from one generator in a fixed order,
// so that a seed and an index name the same case from one version to the next; spread over
// helpers, that order is easy to change unseen.
Case make_case(int i, const Options& o) {
  std::mt19937_64 rng(o.seed + unsigned(i));
  Case c;
  c.n = o.quick ? pick(rng, std::vector<int>{32, 48, 64})
                : pick(rng, std::vector<int>{32, 48, 64, 96, 128});
  const double mu = uniform(rng, 0.05, 1.5);
  const double shape = uniform(rng, 0, 1);
  const std::string type = shape < 0.5 ? "sphere" : shape < 0.85 ? "rough" : "flat";
  const bool elastic = uniform(rng, 0, 1) < 0.5;
  const bool cerruti = uniform(rng, 0, 1) < 0.4;
  const bool partition = uniform(rng, 0, 1) < 0.3;
  const bool periodic = uniform(rng, 0, 1) < 0.15;
  const double direction = uniform(rng, 0, 1) < 0.6 ? 0.0 : uniform(rng, 0.0, 90.0);
  const double E = 210e9, nu = uniform(rng, 0.0, 0.5);
  const double E2 = elastic ? E * std::pow(10.0, uniform(rng, -1, 1)) : 0.0;
  const double nu2 = uniform(rng, 0.0, 0.5);
  std::ostringstream s;
  s << "[material]\nE = " << E << "\nnu = " << nu << "\nmu = " << mu << '\n';
  if (elastic) s << "E2 = " << E2 << "\nnu2 = " << nu2 << '\n';
  double Fz, length;
  std::string surface;
  if (type == "rough") {
    length = 1e-3, Fz = uniform(rng, 50, 300);
    std::ostringstream r;
    r << "[surface]\ntype = rough\nhurst = " << uniform(rng, 0.3, 0.9)
      << "\nrms_slope = " << std::pow(10.0, uniform(rng, -2, std::log10(0.2)))
      << "\nseed = " << std::uniform_int_distribution<int>(1, 1000)(rng) << '\n';
    surface = r.str();
  } else if (type == "flat") {  // a flat punch as wide as the domain
    length = 1e-3, Fz = uniform(rng, 50, 300);
    surface = "[surface]\ntype = flat\n";
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
  s << "[grid]\nn = " << c.n << "\nlength = " << length << (periodic ? "\nperiodic = true" : "")
    << '\n'
    << surface;
  const std::string base = s.str();
  // The full-sliding shift U* = mu (E*/G*) delta, delta from a free-boundary solve (a periodic
  // grid has no finite approach): the scale of the displacement amplitudes.
  std::string free_base = base;
  if (periodic) free_base.erase(free_base.find("\nperiodic = true"), 16);
  Material m = parse_scenario(base + "[load]\nnormal_force = 1\n", "robustness", ".").material;
  const double ustar =
      mu * m.E_star() / m.G_star() * indentation(free_base + "[load]\nnormal_force = 1\n", Fz);
  const Law law = friction_law(rng, mu, ustar, Fz / (length * length));
  // Kinds: 0 force sine, 1 shift sine, 2/3 tables with an oscillating normal force (force,
  // shift), 4 a table reversing at every row, 5 a triangle, 6 a 2-D elliptic path, 7 the
  // normal force down to near zero and back, 8 a ramp.
  const int kind = std::uniform_int_distribution<int>(0, 8)(rng);
  // A sine needs 4 steps per cycle (its turning points); a table reversing at every row has
  // 2 rows per cycle.
  std::vector<int> spcs{2, 4, 8, 16, 32, 64, 128, 256};
  spcs.erase(spcs.begin() + (o.quick ? 6 : 8), spcs.end());
  if (kind != 4) spcs.erase(spcs.begin());
  const int spc = pick(rng, spcs);
  // Amplitudes log-uniform from 1e-3 (deep partial slip) to 0.99 mu F_z, and from 1e-3 to 10
  // times the full-sliding shift.
  const double force_amp = 0.99 * law.lowest * std::pow(10.0, uniform(rng, -3, 0));
  const double disp_amp = ustar * std::pow(10.0, uniform(rng, -3, 1));
  const bool force = kind == 0 || kind == 2 || (kind >= 4 && uniform(rng, 0, 1) < 0.5);
  const int cycles = o.quick ? 1 : 2;
  std::ostringstream load, name;
  load << "[load]\n";
  name << type << (elastic ? "/elastic" : "/rigid") << " n=" << c.n << " mu=" << mu << " nu=" << nu
       << (cerruti ? " cerruti" : " analogy") << (partition ? " partition" : " projected")
       << (periodic ? " periodic" : "")
       << ((kind <= 1 || kind == 8) ? " dir=" + std::to_string(direction) : "") << law.name
       << (force ? " force " + std::to_string(force_amp)
                 : " shift " + std::to_string(disp_amp / ustar) + "U*");
  if (kind <= 1 || kind == 8) {  // sine or ramp, constant normal force
    load << "direction = " << direction << "\nnormal_force = " << Fz
         << "\ncontrol = " << (force ? "force" : "displacement") << '\n';
    if (force)
      load << "amplitude = " << force_amp << '\n';
    else
      load << "displacement_amplitude = " << disp_amp << '\n';
    if (kind == 8) {
      c.steps = std::max(2, spc / 4) + 1;
      load << "path = ramp\nsteps = " << c.steps - 1 << '\n', name << " ramp";
    } else {
      c.steps = spc * cycles + 1;
      load << "path = sine\ncycles = " << cycles << "\nsteps_per_cycle = " << spc << '\n',
          name << " sine";
    }
  } else {  // tables, one period each
    const bool flat_normal = kind == 4 || kind == 5 || kind == 6;
    const double floor = std::pow(10.0, uniform(rng, -6, -2));  // kind 7: lowest Fz / Fz
    const int rows = kind == 4 ? spc : spc + 1;
    std::ostringstream t;
    const bool two = kind == 6;
    t << "time,Fz," << (force ? "Fx" : "Ux") << (two ? force ? ",Fy" : ",Uy" : "") << '\n';
    const double ratio = uniform(rng, -1, 1);  // kind 6: the ellipse's minor / major axis
    for (int k = 0; k < rows; ++k) {
      const double ph = 2 * M_PI * k / spc;
      double fz = Fz;
      if (!flat_normal)
        fz = kind == 7 ? Fz * (floor + (1 - floor) * 0.5 * (1 + std::cos(ph)))
                       : Fz * (1 + 0.3 * std::sin(ph + 0.7));
      double q = std::sin(ph), q2 = ratio * std::cos(ph) - ratio;
      if (kind == 4) q = k == 0 ? 0.0 : (k % 2 ? 1 : -1) * uniform(rng, 0.2, 1.0);
      if (kind == 5) q = 2 / M_PI * std::asin(std::sin(ph));  // triangle
      // A 2-D force path stays inside the disc |F| <= amplitude mu F_z.
      const double scale =
          force ? force_amp * mu * fz / (two ? std::sqrt(1 + 4 * ratio * ratio) : 1.0) : disp_amp;
      t << k << ',' << fz << ',' << q * scale;
      if (two) t << ',' << q2 * scale;
      t << '\n';
    }
    c.table = t.str();
    load << "path = table\ntable = table.csv\ncontrol = " << (force ? "force" : "displacement")
         << '\n';
    static const char* names[] = {"",
                                  "",
                                  " table oscillating Fz",
                                  " table oscillating Fz",
                                  " table reversing",
                                  " table triangle",
                                  " table 2-D ellipse",
                                  " table Fz to near zero"};
    name << names[kind];
    if (kind == 7) name << " (" << floor << " Fz)";
    c.steps = rows;
  }
  name << " steps=" << c.steps;
  c.scenario = base + load.str() + law.text +
               "[solver]\nstiffness = false\ncoupling = " + (cerruti ? "cerruti" : "analogy") +
               "\nalgorithm = " + (partition ? "partition" : "projected") +
               "\n[output]\nfields = none\n";
  c.name = name.str();
  return c;
}

struct Outcome {
  int exit = 0;
  double seconds = 0.0, cpu = 0.0;  // wall time; the child's CPU time (user + system)
  long iterations = 0, max_iterations = 0;
  bool fallback = false;
};

// CPU time of the finished children (s): comparable across machine loads, unlike wall time.
double children_cpu() {
  rusage u{};
  getrusage(RUSAGE_CHILDREN, &u);
  auto s = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
  return s(u.ru_utime) + s(u.ru_stime);
}

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
  const double cpu0 = children_cpu();
  const int status = std::system(cmd.c_str());
  r.seconds = bench::seconds_since(t0);
  r.cpu = children_cpu() - cpu0;
  r.exit = WIFEXITED(status) ? WEXITSTATUS(status) : 128;
  std::ifstream err(dir / "stderr.txt");
  std::string line;
  // The fallback's own note (other notes, e.g. a ramp ending below full sliding, are not).
  while (std::getline(err, line))
    r.fallback |= line.find("did not converge with the chosen algorithm") != std::string::npos;
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
    else if (a == "--list")
      o.list = true;
    else if (a == "--first")
      o.first = std::stoi(next());
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
  csv << "case,exit,seconds,cpu_seconds,tangential_iterations,max_tangential_iterations,fallback,"
         "steps,"
         "description\n";
  int failures = 0, fallbacks = 0;
  double total = 0.0, cpu = 0.0;
  for (int i = o.first; i < o.first + o.cases; ++i) {
    const Case c = make_case(i, o);
    if (o.list) {
      std::printf("case %d: %s\n", i, c.name.c_str());
      continue;
    }
    const Outcome r = run_case(c, i, o);
    failures += r.exit != 0, fallbacks += r.fallback, total += r.seconds, cpu += r.cpu;
    csv << i << ',' << r.exit << ',' << r.seconds << ',' << r.cpu << ',' << r.iterations << ','
        << r.max_iterations << ',' << r.fallback << ',' << c.steps << ",\"" << c.name << "\"\n";
    csv.flush();
    if (r.exit != 0 || r.fallback)
      std::printf("case %d: exit %d%s (%s), see %s\n", i, r.exit, r.fallback ? ", fallback" : "",
                  c.name.c_str(), (o.out / ("case_" + std::to_string(i))).string().c_str());
    else
      fs::remove_all(o.out / ("case_" + std::to_string(i)));
  }
  std::printf("bench_robustness: %d cases, %d failures, %d with a fallback, %.1f s (%.1f s CPU)\n",
              o.cases, failures, fallbacks, total, cpu);
  return failures ? 1 : 0;
}
