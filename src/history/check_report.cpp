// `fretbem check` report lines (see check_report.hpp).
#include "fretbem/history/check_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "fretbem/core/format.hpp"
#include "fretbem/history/preflight.hpp"

namespace fretbem {

namespace {

// Four significant digits: a report to read, not a value to reuse.
std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", v);
  return b;
}

bool given(const Scenario& sc, const std::string& key) {
  return std::binary_search(sc.given_keys.begin(), sc.given_keys.end(), key);
}

// Keys that have no effect under the scenario's path and control: (key, why) pairs.
std::vector<std::pair<std::string, std::string>> ignored_keys(const Scenario& sc) {
  const LoadSpec& l = sc.load;
  std::vector<std::pair<std::string, std::string>> out;
  auto unused = [&](const char* key, const std::string& why) {
    if (given(sc, key)) out.emplace_back(key, why);
  };
  const bool scripted = l.path == PathType::ramp || l.path == PathType::sine;
  if (!scripted || l.control == Control::displacement)
    unused("load.amplitude", scripted ? "load.control = displacement" : "this load.path");
  if (!scripted || l.control == Control::force)
    unused("load.displacement_amplitude", scripted ? "load.control = force" : "this load.path");
  if (l.path != PathType::sine) {
    unused("load.cycles", "load.path is not sine");
    unused("load.steps_per_cycle", "load.path is not sine");
  }
  if (l.path != PathType::ramp) unused("load.steps", "load.path is not ramp");
  if (l.path != PathType::table) unused("load.table", "load.path is not table");
  if (l.path == PathType::none || l.path == PathType::table)
    unused("load.direction", "load.path = none or table");
  if (l.path == PathType::table) unused("load.control", "a table's columns choose the control");
  if (sc.surface.type != SurfaceType::sphere)
    unused("surface.radius", "surface.type is not sphere");
  if (sc.surface.type != SurfaceType::file) {
    unused("surface.file", "surface.type is not file");
    unused("surface.dataset", "surface.type is not file");
  }
  if (sc.wear.law != WearLaw::none) unused("load.cycles", "wear runs ignore load.cycles");
  if (sc.solver.coupling != Coupling::coupled) {
    unused("solver.coupling_tolerance", "solver.coupling is not coupled");
    unused("solver.coupling_iterations", "solver.coupling is not coupled");
  }
  return out;
}

void wear_lines(const Model& m, std::ostringstream& o) {
  const WearSpec& w = m.scenario.wear;
  if (w.law == WearLaw::none) return;
  o << "  wear: " << format_count(w.cycles)
    << " load cycles (wear.cycles); wear runs ignore load.cycles and simulate the first\n"
    << "        period of the load path (docs/wear.md)\n";
}

}  // namespace

std::string check_report(const Model& m) {
  const Scenario& sc = m.scenario;
  const ContactScales s = contact_scales(sc, m.path, m.surface0);
  std::ostringstream o;
  o << "  E* = " << num(s.E_star) << " Pa, G* = " << num(s.G_star)
    << " Pa, mu = " << num(sc.material.mu) << "\n";
  o << "  Dundurs beta = " << num(sc.material.dundurs_beta())
    << (sc.solver.coupling == Coupling::coupled
            ? " (normal-tangential coupling solved)\n"
            : " (normal-tangential coupling neglected; solver.coupling = coupled solves it)\n");
  o << "  cell h = " << num(sc.grid.h) << " m, domain " << num(sc.grid.h * sc.grid.nx) << " x "
    << num(sc.grid.h * sc.grid.ny) << " m" << (sc.grid.periodic ? " (periodic)" : "") << "\n";
  if (s.hertz_a > 0.0)
    o << "  Hertz at Fz = " << num(s.max_normal_force) << " N: a = " << num(s.hertz_a)
      << " m, p0 = " << num(s.hertz_p0) << " Pa, delta = " << num(s.hertz_delta) << " m\n";
  if (s.full_sliding_shift > 0.0)
    o << "  full-sliding shift U* = mu delta E*/G* = " << num(s.full_sliding_shift) << " m\n";
  if (sc.wear.law == WearLaw::none)
    o << "  " << m.path.steps.size() << " load steps (each one normal and one tangential solve)\n";
  o << "  memory: about " << num(std::round(estimated_peak_bytes(sc) / (1 << 20))) << " MiB\n";
  wear_lines(m, o);
  for (const auto& [key, why] : ignored_keys(sc))
    o << "  warning: " << key << " is ignored (" << why << ")\n";
  return o.str();
}

}  // namespace fretbem
