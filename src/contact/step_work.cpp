#include "fretbem/contact/step_work.hpp"

#include <algorithm>
#include <cmath>

namespace fretbem {

// Weights of the bound and pressure at the step's start and end along node k's slip of length
// len (step_work.hpp).
BoundWeights bound_weights(const StepStart* start, const InterfaceState& end, const Field& bound,
                           const VecField& s, double len, Eigen::Index k) {
  const auto slip = std::uint8_t(NodeState::slip);
  if (end.state(k) == slip) {
    if (start && start->state(k) == slip) return {0.5, 0.5};
    return {0.0, 1.0};
  }
  if (!start || bound(k) > 0.0 || !(start->bound(k) > 0.0)) return {};
  double ts = 0.0;
  for (std::size_t c = 0; c < s.size(); ++c) ts += start->traction[c](k) * s[c](k);
  if (!(ts > 0.0) || !(len > 0.0)) return {};
  const double g0 = start->bound(k), theta = start->loss ? (*start->loss)(k) : 1.0;
  const double work = theta * ts + (1.0 - theta) * start->tangential_self * g0 * g0;
  return {0.5 * std::clamp(work / (g0 * len), 0.0, 1.0), 0.0};
}

void step_work(const StepStart* start, const InterfaceState& end, const Field& bound,
               const VecField& s, StepWork& out) {
  out.pressure.resize(bound.rows(), bound.cols());
  out.work.resize(bound.rows(), bound.cols());
  for (Eigen::Index k = 0; k < bound.size(); ++k) {
    const BoundWeights w = bound_weights(start, end, bound, s, out.slip(k), k);
    const double g0 = start ? start->bound(k) : 0.0, p0 = start ? start->pressure(k) : 0.0;
    out.pressure(k) = w.start * p0 + w.end * end.pressure(k);
    out.work(k) = (w.start * g0 + w.end * bound(k)) * out.slip(k);
  }
}

}  // namespace fretbem
