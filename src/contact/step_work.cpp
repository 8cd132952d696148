#include "fretbem/contact/step_work.hpp"

#include <algorithm>
#include <cmath>

namespace fretbem {

namespace {

// A node slipping at both ends of the step: the trapezoid, or the three-point rule where the
// node slipped through the step before on a path C1 between the two (step_work.hpp).
BoundWeights slipping_through(const StepStart& start, const Field& bound, double len,
                              Eigen::Index k) {
  const BoundWeights trapezoid{0.5, 0.5, 0.0};
  const StepBefore* b = start.before;
  if (!b || !(b->slip(k) > 0.0) || !(len > 0.0) || !(b->span > 0.0) || !(b->span_next > 0.0))
    return trapezoid;
  const double h0 = b->span, h1 = b->span_next;
  const double c = h1 * h1 / (6.0 * h0 * (h0 + h1)), r = b->slip(k) / len;
  const BoundWeights w{0.5 + c * r, 0.5 - c * r, c};
  const double mean =
      w.start * start.bound(k) + w.end * bound(k) + w.change_before * b->bound_change(k);
  return mean >= 0.0 ? w : trapezoid;
}

}  // namespace

// Weights of the bound and pressure at the step's start and end along node k's slip of length
// len (step_work.hpp).
BoundWeights bound_weights(const StepStart* start, const InterfaceState& end, const Field& bound,
                           const VecField& s, double len, Eigen::Index k) {
  const auto slip = std::uint8_t(NodeState::slip);
  if (end.state(k) == slip) {
    if (start && start->state(k) == slip) return slipping_through(*start, bound, len, k);
    return {0.0, 1.0, 0.0};
  }
  if (!start || bound(k) > 0.0 || !(start->bound(k) > 0.0)) return {};
  double ts = 0.0;
  for (std::size_t c = 0; c < s.size(); ++c) ts += start->traction[c](k) * s[c](k);
  if (!(ts > 0.0) || !(len > 0.0)) return {};
  const double g0 = start->bound(k), theta = start->loss ? (*start->loss)(k) : 1.0;
  const double work = theta * ts + (1.0 - theta) * start->tangential_self * g0 * g0;
  return {0.5 * std::clamp(work / (g0 * len), 0.0, 1.0), 0.0, 0.0};
}

namespace {

// Node k's pressure along the slip and work (step_work).
void node_work(const StepStart* start, const InterfaceState& end, const Field& bound,
               const VecField& s, StepWork& out, Eigen::Index k) {
  const BoundWeights w = bound_weights(start, end, bound, s, out.slip(k), k);
  const double g0 = start ? start->bound(k) : 0.0, p0 = start ? start->pressure(k) : 0.0;
  const StepBefore* b = start ? start->before : nullptr;
  const double dg = b ? b->bound_change(k) : 0.0, dp = b ? b->pressure_change(k) : 0.0;
  out.pressure(k) = w.start * p0 + w.end * end.pressure(k) + w.change_before * dp;
  out.work(k) = (w.start * g0 + w.end * bound(k) + w.change_before * dg) * out.slip(k);
}

}  // namespace

void step_work(const StepStart* start, const InterfaceState& end, const Field& bound,
               const VecField& s, StepWork& out) {
  out.pressure.resize(bound.rows(), bound.cols());
  out.work.resize(bound.rows(), bound.cols());
  for (Eigen::Index k = 0; k < bound.size(); ++k) node_work(start, end, bound, s, out, k);
}

void step_work(const InterfaceState& end, const Field& bound, const VecField& s, StepWork& out,
               std::span<const Eigen::Index> nodes) {
  for (const Eigen::Index k : nodes) node_work(nullptr, end, bound, s, out, k);
}

}  // namespace fretbem
