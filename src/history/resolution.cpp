#include "fretbem/history/resolution.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/format.hpp"
#include "fretbem/history/preflight.hpp"

namespace fretbem {

namespace {

bool in_contact(const StateField& s, Eigen::Index i, Eigen::Index j) {
  return s(i, j) != std::uint8_t(NodeState::open);
}

// Cell edges between a contact node and a non-contact one (or the domain's edge).
long contact_edges(const StateField& s) {
  long edges = 0;
  const Eigen::Index nx = s.rows(), ny = s.cols();
  for (Eigen::Index j = 0; j < ny; ++j)
    for (Eigen::Index i = 0; i < nx; ++i) {
      if (!in_contact(s, i, j)) continue;
      edges += (i == 0 || !in_contact(s, i - 1, j)) + (i + 1 == nx || !in_contact(s, i + 1, j)) +
               (j == 0 || !in_contact(s, i, j - 1)) + (j + 1 == ny || !in_contact(s, i, j + 1));
    }
  return edges;
}

std::string percent(double share) {
  return format_number(std::round(share * 1e3) / 10) + " %";
}

}  // namespace

double slip_ring_cells(const StateField& state) {
  const long slip = (state == std::uint8_t(NodeState::slip)).count();
  return slip_ring_width(slip, contact_edges(state));
}

double slip_ring_width(long slip, long edges) {
  return slip == 0 || edges == 0 ? 0.0 : double(slip) / (M_PI / 4 * double(edges));
}

bool load_exceeds(double a, double b) {
  return a > b + kSameLoad * std::abs(b);
}

bool load_peak(const StepRecord& r, const StepRecord& prev) {
  return r.turning && r.step > 0 &&
         !load_exceeds(std::hypot(prev.Fx, prev.Fy), std::hypot(r.Fx, r.Fy));
}

long contact_nodes(const StateField& state) {
  return (state != std::uint8_t(NodeState::open)).count();
}

double edge_load_share(const Field& p) {
  const double total = p.sum();
  if (!(total > 0.0)) return 0.0;
  const Eigen::Index nx = p.rows(), ny = p.cols();
  double edge = p.row(0).sum() + p.col(0).sum();
  if (nx > 1) edge += p.row(nx - 1).sum();
  if (ny > 1) edge += p.col(ny - 1).sum();
  edge -= p(0, 0) + p(nx - 1, 0) * (nx > 1) + p(0, ny - 1) * (ny > 1) +
          p(nx - 1, ny - 1) * (nx > 1 && ny > 1);  // corners counted twice
  return edge / total;
}

void check_edge_contact(const Scenario& sc, double share, const std::string& where) {
  // Rough, flat and measured surfaces: the square domain is the nominal contact (the paper's
  // setting), so contact on its edge is reported, not refused.
  if (sc.surface.type != SurfaceType::sphere) return;
  if (sc.grid.periodic || sc.allow_edge_contact || !(share > kEdgeLoadShareLimit)) return;
  throw InputError(where + ": " + percent(share) +
                   " of the normal load is on the outermost cells of the free-boundary grid "
                   "(grid.length = " +
                   format_number(sc.grid.length_x()) +
                   " m): the contact does not fit and the answer depends on the domain; enlarge "
                   "grid.length, or set grid.allow_edge_contact = true to run anyway");
}

std::optional<SpherePrediction> predict_sphere(const Scenario& sc) {
  if (sc.surface.type != SurfaceType::sphere || sc.surface.radius <= 0) return std::nullopt;
  const LoadSpec& l = sc.load;
  if (!l.normal_force && !l.indentation) return std::nullopt;
  const Material& m = sc.material;
  const double R = sc.surface.radius, Es = m.E_star(), h = sc.grid.h, L = sc.grid.length_x();
  SpherePrediction p;
  // Hertz (Johnson, Contact Mechanics, eqs. 4.22-4.23): a^3 = 3 P R / (4 E*), delta = a^2 / R.
  p.a = l.normal_force ? closed_forms::hertz_contact_radius(*l.normal_force, R, Es)
                       : std::sqrt(R * *l.indentation);
  p.a_over_h = p.a / h;
  p.contact_nodes = M_PI * p.a_over_h * p.a_over_h;
  p.ustar =
      closed_forms::full_sliding_shift(m.mu, closed_forms::hertz_approach(p.a, R), Es, m.G_star());
  const bool cyclic = l.path == PathType::ramp || l.path == PathType::sine;
  if (cyclic && l.control == Control::force) p.q = l.amplitude;
  if (cyclic && l.control == Control::displacement) {
    p.q = closed_forms::cattaneo_force_ratio(l.displacement_amplitude / p.ustar);
    if (l.path == PathType::ramp) p.ramp_ratio = p.ustar / l.displacement_amplitude;
  }
  if (p.q > 0) {
    // Slip ring width a - c (Cattaneo c/a).
    const double w = p.a * (1 - closed_forms::cattaneo_stick_ratio(std::min(p.q, 1.0)));
    p.ring_cells = w / h;
    p.suggested_n = int(std::ceil(kMinRingCells * L / w));
  }
  // Load outside the circle through the outermost cells' inner faces, r0 = L/2 - h:
  // P_out / P = (1 - r0^2/a^2)^(3/2) for the Hertz pressure.
  const double r0 = std::min(L, sc.grid.length_y()) / 2 - h;
  if (!sc.grid.periodic && p.a > r0)
    p.edge_share = std::pow(1 - std::pow(std::max(r0, 0.0) / p.a, 2), 1.5);
  return p;
}

std::optional<SpherePrediction> predict_sphere(const Scenario& sc, const LoadPath& path) {
  double force = 0.0, indentation = 0.0;
  for (const LoadStep& st : path.steps) {
    double& peak = st.normal.force_control ? force : indentation;
    peak = std::max(peak, st.normal.value);
  }
  Scenario at_peak = sc;
  if (force > 0.0)
    at_peak.load.normal_force = force, at_peak.load.indentation.reset();
  else if (indentation > 0.0)
    at_peak.load.indentation = indentation, at_peak.load.normal_force.reset();
  return predict_sphere(at_peak);
}

std::vector<std::string> describe(const SpherePrediction& p, const Scenario& sc) {
  std::vector<std::string> out;
  auto num = [](double v) { return format_number(std::round(v * 100) / 100); };
  out.push_back("Hertz contact radius a = " + format_number(p.a) + " m = " + num(p.a_over_h) +
                " cells, about " + num(std::round(p.contact_nodes)) + " contact nodes (" +
                percent(p.contact_nodes / (double(sc.grid.nx) * sc.grid.ny)) + " of the domain)");
  if (p.q > 0 && p.q < 1)
    out.push_back("slip ring at the load peaks a (1 - (1 - q)^(1/3)) = " + num(p.ring_cells) +
                  " cells (q = " + num(p.q) + ")");
  if (p.q >= 1)
    out.push_back("gross slip: the whole contact slips (full-sliding shift U* = " +
                  format_number(p.ustar) + " m)");
  if (p.q > 0 && p.q < 1 && p.ring_cells < kMinRingCells) {
    const double w = p.ring_cells * sc.grid.h;
    out.push_back(
        "warning: the slip ring spans under " + num(kMinRingCells) +
        " cells: dissipation and slip are under-resolved (Mindlin-Deresiewicz energy "
        "-2.5 % at 1.3 cells, nothing may slip below 1); use grid.n >= " +
        std::to_string(p.suggested_n) + ", or grid.length = " + format_number(3 * p.a) +
        " (3a) with grid.n >= " + std::to_string(int(std::ceil(kMinRingCells * 3 * p.a / w))));
  }
  if (p.edge_share > 0)
    out.push_back(
        "warning: the Hertz contact reaches the outermost cells of the free-boundary "
        "grid (about " +
        percent(p.edge_share) + " of the load outside radius grid.length/2 - h); " +
        (p.edge_share > kEdgeLoadShareLimit && !sc.allow_edge_contact
             ? "the run will refuse it above " + percent(kEdgeLoadShareLimit) +
                   " unless grid.allow_edge_contact = true; "
             : "") +
        "use grid.length >= " + format_number(2.4 * p.a));
  if (p.ramp_ratio > 1)
    out.push_back("warning: the displacement ramp ends below full sliding: U*/amplitude = " +
                  num(p.ramp_ratio) + " (U* = " + format_number(p.ustar) + " m)");
  return out;
}

}  // namespace fretbem
