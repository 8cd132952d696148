// Edge-contact refusal decided before a run (see edge_preflight.hpp).
#include "fretbem/history/edge_preflight.hpp"

#include <string>
#include <vector>

#include "fretbem/history/resolution.hpp"

namespace fretbem {

namespace {

// Steps at which the normal load of one control kind first reaches a new maximum.
std::vector<std::size_t> new_peak_steps(const LoadPath& path) {
  std::vector<std::size_t> out;
  double force = 0.0, indentation = 0.0;
  for (std::size_t k = 0; k < path.steps.size(); ++k) {
    const NormalLoad& n = path.steps[k].normal;
    double& peak = n.force_control ? force : indentation;
    if (out.empty() || n.value > peak) out.push_back(k);
    peak = std::max(peak, n.value);
  }
  return out;
}

double solved_share(const Model& m, std::size_t step) {
  const NormalLoad& n = m.path.steps[step].normal;
  Field p = Field::Zero(m.surface0.rows(), m.surface0.cols());
  if (n.force_control)
    m.normal->solve_force(m.surface0, n.value, p);
  else
    m.normal->solve_indentation(m.surface0, n.value, p);
  return edge_load_share(p);
}

}  // namespace

void check_edge_contact_of_path(const Scenario& sc, const LoadPath& path) {
  if (sc.surface.type != SurfaceType::sphere || sc.grid.periodic || sc.allow_edge_contact) return;
  const auto hertz = predict_sphere(sc, path);
  if (!hertz || !(hertz->edge_share > kEdgeLoadShareLimit)) return;
  const auto m = build_model(sc);
  const std::vector<std::size_t> peaks = new_peak_steps(m->path);
  // First peak step whose solved share exceeds the limit: the step run refuses.
  std::size_t lo = 0, hi = peaks.size();
  double share_at_hi = 0.0;
  while (lo < hi) {
    const std::size_t mid = (lo + hi) / 2;
    const double share = solved_share(*m, peaks[mid]);
    if (share > kEdgeLoadShareLimit)
      hi = mid, share_at_hi = share;
    else
      lo = mid + 1;
  }
  if (hi < peaks.size()) check_edge_contact(sc, share_at_hi, "step " + std::to_string(peaks[hi]));
}

}  // namespace fretbem
