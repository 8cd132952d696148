// `fretbem check` report lines (see check_report.hpp).
#include "fretbem/history/check_report.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "fretbem/core/format.hpp"
#include "fretbem/history/cost_estimate.hpp"
#include "fretbem/history/preflight.hpp"
#include "fretbem/history/step_control.hpp"
#include "fretbem/surface/formats.hpp"

namespace fretbem {

namespace {

// Four significant digits: a report to read, not a value to reuse.
std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", v);
  return b;
}

// Where the spacing the run uses was checked from, or that nothing checked it.
std::string spacing_origin(const SurfaceSpec& s) {
  const HeightMap file = read_height_map(s.file, s.dataset, s.layout);
  if (file.dx || file.dy) return "the file's, checked against grid.length / n";
  if (s.spacing) return "surface.spacing, checked against grid.length / n";
  return "grid.length / n: neither the file nor surface.spacing gives one to check";
}

// A loaded height map as the run sees it: shape, range, rms and the spacing's origin.
void height_map_lines(const Model& m, std::ostringstream& o) {
  const Scenario& sc = m.scenario;
  if (sc.surface.type != SurfaceType::file) return;
  const Field& z = m.surface0;
  const double mean = z.mean();
  const double rms = std::sqrt((z.array() - mean).square().mean());
  o << "  height map " << sc.surface.file.string() << ": " << z.rows() << " x " << z.cols()
    << " (x by y), heights " << num(z.minCoeff()) << " .. " << num(z.maxCoeff()) << " m, rms "
    << num(rms) << " m about the mean\n"
    << "  height map spacing " << num(sc.grid.h) << " m (" << spacing_origin(sc.surface) << ")\n";
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
  height_map_lines(m, o);
  if (s.hertz_a > 0.0)
    o << "  Hertz at Fz = " << num(s.max_normal_force) << " N: a = " << num(s.hertz_a)
      << " m, p0 = " << num(s.hertz_p0) << " Pa, delta = " << num(s.hertz_delta) << " m\n";
  o << "  full-sliding shift U* = mu delta E*/G* = " << num(s.full_sliding_shift) << " m"
    << (s.approach_known ? "" : " at most (delta bounded by the largest displacement scale)")
    << "\n";
  if (sc.wear.law == WearLaw::none)
    o << "  " << m.path.steps.size() << " load steps (each one normal and one tangential solve)\n";
  o << "  memory: about "
    << num(std::round(estimate_memory(sc, m.cycle_predictor, predictor_bytes_per_cell(sc, m.path),
                                      repeat_bytes_per_cell(sc, m.path))
                          .total() /
                      (1 << 20)))
    << " MiB\n";
  wear_lines(m, o);
  return o.str();
}

}  // namespace fretbem
