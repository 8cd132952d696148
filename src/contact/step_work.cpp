#include "fretbem/contact/step_work.hpp"

#include <algorithm>
#include <cmath>

namespace fretbem {

namespace {

// Weights (w0, w1) of the bound and pressure at the step's start and end along node k's slip
// (step_work.hpp).
struct Weights {
  double start = 0.0, end = 0.0;
};

Weights weights(const StepStart* start, const InterfaceState& end, const Field& bound,
                Eigen::Index k) {
  const auto slip = std::uint8_t(NodeState::slip);
  if (end.state(k) == slip) {
    if (start && start->state(k) == slip) return {0.5, 0.5};
    return {0.0, 1.0};
  }
  if (!start || bound(k) > 0.0 || !(start->bound(k) > 0.0)) return {};
  double t2 = 0.0;
  for (const auto& t : start->traction) t2 += t(k) * t(k);
  return {0.5 * std::min(std::sqrt(t2) / start->bound(k), 1.0), 0.0};
}

}  // namespace

void step_work(const StepStart* start, const InterfaceState& end, const Field& bound,
               StepWork& out) {
  out.pressure.resize(bound.rows(), bound.cols());
  out.work.resize(bound.rows(), bound.cols());
  for (Eigen::Index k = 0; k < bound.size(); ++k) {
    const Weights w = weights(start, end, bound, k);
    const double g0 = start ? start->bound(k) : 0.0, p0 = start ? start->pressure(k) : 0.0;
    out.pressure(k) = w.start * p0 + w.end * end.pressure(k);
    out.work(k) = (w.start * g0 + w.end * bound(k)) * out.slip(k);
  }
}

}  // namespace fretbem
