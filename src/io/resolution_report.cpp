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

void ResolutionReport::on_step(const StepRecord& r, const InterfaceState&, const Model& m) {
  edge_share_ = std::max(edge_share_, r.edge_load_share);
  const bool peak = load_peak(r, last_);
  last_ = r;
  if (!peak) return;
  if (ring_ < 0 || r.slip_ring_cells < ring_) {
    ring_ = r.slip_ring_cells, nodes_ = r.contact_nodes;
    radius_cells_ = std::sqrt(r.contact_area / M_PI) / m.scenario.grid.h;
  }
}

void ResolutionReport::on_finish(const InterfaceState&, const Model& m) {
  const Scenario& sc = m.scenario;
  const bool sphere = sc.surface.type == SurfaceType::sphere;
  if (ring_ >= 0) {
    summary_ = "resolution: slip ring " + two_digits(ring_) +
               " cells at the load peaks (narrowest), " + std::to_string(nodes_) +
               " contact nodes" + (sphere ? ", a/h = " + two_digits(radius_cells_) : "");
    if (ring_ == 0)
      warnings_.push_back(
          "WARNING: no node slips at a load peak: the slip zone is below one cell and the "
          "dissipation and slip are lost; refine the grid (fretbem check suggests one for "
          "spheres)");
    else if (ring_ < kMinRingCells)
      warnings_.push_back("WARNING: the slip ring at the load peaks spans only " +
                          two_digits(ring_) + " cells (< " + two_digits(kMinRingCells) +
                          "): dissipation and slip are under-resolved (Mindlin-Deresiewicz "
                          "energy -2.5 % to -6.9 % below two cells); refine the grid (fretbem "
                          "check suggests one for spheres)");
  }
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
