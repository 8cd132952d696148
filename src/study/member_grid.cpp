#include "fretbem/study/member_grid.hpp"

#include <algorithm>
#include <cmath>

#include "fretbem/history/resolution.hpp"

namespace fretbem {

namespace {

int round_up_to_8(int n) {
  return (n + 7) / 8 * 8;
}

}  // namespace

MemberGrid choose_member_grid(const Scenario& sc, int max_grid_n) {
  MemberGrid g;
  g.n = g.base_n = sc.grid.nx;
  const auto p = predict_sphere(sc);
  if (!p || !(p->q > 0)) return g;  // no cyclic tangential load on a sphere: nothing to predict
  if (p->q >= 1) return g.resolution = "gross slip", g;
  // The ring's width in metres does not depend on the grid: its cell count scales with n.
  const double width = p->ring_cells * sc.grid.h;
  const auto cells_on = [&](int n) { return width / (sc.grid.length_x() / n); };
  g.ring_cells = p->ring_cells;
  if (g.ring_cells >= kMinRingCells) return g.resolution = "resolved", g;
  const int needed = round_up_to_8(p->suggested_n);
  // Rectangular grids keep their cells: refining one side alone would change the cell shape.
  if (max_grid_n > g.base_n && sc.grid.nx == sc.grid.ny) {
    g.n = std::min(needed, max_grid_n);
    g.ring_cells = cells_on(g.n);
  }
  g.resolution = g.ring_cells >= kMinRingCells
                     ? "refined from " + std::to_string(g.base_n)
                     : "under-resolved: needs grid.n >= " + std::to_string(needed);
  return g;
}

}  // namespace fretbem
