#include "fretbem/io/resolution_report.hpp"

#include <cmath>

#include "fretbem/core/format.hpp"
#include "fretbem/history/resolution.hpp"

namespace fretbem {

namespace {

std::string two_digits(double v) {
  return format_number(std::round(v * 100) / 100);
}

}  // namespace

void ResolutionReport::keep_peak(const StepRecord& r, double h) {
  nodes_ = r.contact_nodes;
  radius_cells_ = std::sqrt(r.contact_area / M_PI) / h;
}

// A peak reached while the normal load rises, at which no node slips, is skipped: the bound
// grows faster there than the tangential load, so the whole contact sticks at any grid
// (Mindlin-Deresiewicz: no slip where |dQ| < mu dP); its zero ring says nothing of resolution.
void ResolutionReport::on_step(const StepRecord& r, const InterfaceState&, const Model& m) {
  edge_share_ = std::max(edge_share_, r.edge_load_share);
  const bool peak = load_peak(r, last_);
  const bool rising = load_exceeds(r.Fz, last_.Fz);
  last_ = r;
  if (!peak) return;
  if (r.slip_area <= 0 && rising) {
    if (ring_ < 0 && !sliding_peak_ && !stuck_peak_) keep_peak(r, m.scenario.grid.h);
    stuck_peak_ = true;
    return;
  }
  if (r.stick_area <= 0 && r.slip_area > 0) {
    if (ring_ < 0 && !sliding_peak_) keep_peak(r, m.scenario.grid.h);
    sliding_peak_ = true;
    return;
  }
  if (ring_ < 0 || r.slip_ring_cells < ring_) {
    ring_ = r.slip_ring_cells;
    keep_peak(r, m.scenario.grid.h);
  }
}

// The words follow the path (the end of a ramp, the peaks of a cycle) and the surface: the
// Mindlin–Deresiewicz figures hold for a sphere's ring (-2.5 % to -6.9 % below two cells,
// README "Resolution and domain reports"); a rough contact has many slip zones, measured
// together per unit length of the contact edges.
void ResolutionReport::resolution_lines(const Scenario& sc) {
  const bool sphere = sc.surface.type == SurfaceType::sphere;
  const bool ramp = sc.load.path == PathType::ramp;
  const std::string where = ramp ? "at the end of the ramp" : "at the load peaks";
  const std::string nodes = std::to_string(nodes_) + " contact nodes" +
                            (sphere ? ", a/h = " + two_digits(radius_cells_) : "");
  if (ring_ < 0 && !sliding_peak_) {
    summary_ = "resolution: no node slips " + where +
               ", reached while the normal load rises (full stick: no slip " +
               (sphere ? "ring" : "zone") + " to resolve), " + nodes;
    return;
  }
  if (ring_ < 0) {
    summary_ = "resolution: the whole contact slides " + where + " (gross slip: no slip " +
               (sphere ? "ring" : "zone") + " to resolve), " + nodes;
    return;
  }
  const std::string zone = sphere ? "slip ring" : "slip zones (per unit length of contact edge)";
  summary_ = "resolution: " + zone + " " + two_digits(ring_) + " cells " + where +
             (ramp ? "" : " (narrowest)") + (sliding_peak_ ? ", gross slip at other peaks" : "") +
             (stuck_peak_ ? ", full stick at peaks reached under a rising normal load" : "") +
             ", " + nodes;
  const std::string refine = sphere ? "; refine the grid (fretbem check suggests one)"
                                    : "; refine the grid (a larger grid.n at the same grid.length)";
  const std::string lost =
      sphere ? "dissipation and slip" : "stick area, k_x, dissipation and slip";
  if (ring_ == 0)
    warnings_.push_back("WARNING: no node slips " + where + ": the slip " +
                        (sphere ? "ring is" : "zones are") + " below one cell and the " + lost +
                        " are lost" + refine);
  else if (ring_ < kMinRingCells)
    warnings_.push_back(
        "WARNING: the " + zone + " " + where + (sphere ? " spans" : " span") + " only " +
        two_digits(ring_) + " cells (< " + two_digits(kMinRingCells) + "): " + lost +
        " are under-resolved" +
        (sphere ? " (Mindlin-Deresiewicz energy -2.5 % to -6.9 % below two cells)" : "") + refine);
}

void ResolutionReport::on_finish(const InterfaceState&, const Model& m) {
  const Scenario& sc = m.scenario;
  if (ring_ >= 0 || sliding_peak_ || stuck_peak_) resolution_lines(sc);
  if (edge_share_ > 0)
    warnings_.push_back("warning: up to " + two_digits(100 * edge_share_) +
                        " % of the normal load is on the outermost cells of the free-boundary "
                        "grid: the answer depends on the domain; enlarge grid.length");
  const bool disp_ramp = sc.load.path == PathType::ramp && sc.load.control == Control::displacement;
  if (disp_ramp && last_.stick_area - last_.stuck_at_bound_area > 0) {
    // Full sliding (Ciavarella–Jäger): the last stick point moves with the rigid shift
    // U* = mu (E*/G*) delta, delta the approach from first touch.
    const double ustar = sc.material.mu * m.half_space->tangential_ratio() * last_.delta;
    const double amplitude = std::hypot(last_.Ux, last_.Uy);
    warnings_.push_back("note: the displacement ramp ended below full sliding (F_t = " +
                        two_digits(std::hypot(last_.Fx, last_.Fy) / (sc.material.mu * last_.Fz)) +
                        " mu F_z): U*/amplitude = " + two_digits(ustar / amplitude) +
                        " (full-sliding shift U* = mu delta E*/G* = " + format_number(ustar) +
                        " m)");
  }
}

}  // namespace fretbem
