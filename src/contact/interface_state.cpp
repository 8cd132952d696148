#include "fretbem/contact/interface_state.hpp"

#include <cmath>

namespace fretbem {

// The operator's fields: this rank's slab on a distributed grid, the whole grid serially.
InterfaceState InterfaceState::zeros(const TangentialOperator& op) {
  InterfaceState s;
  s.traction = op.zeros();
  s.displacement = op.zeros();
  s.slip = op.zeros();
  const Eigen::Index nx = s.traction[0].rows(), ny = s.traction[0].cols();
  s.pressure = Field::Zero(nx, ny);
  s.state = StateField::Zero(nx, ny);
  s.slip_path = Field::Zero(nx, ny);
  s.dissipation = Field::Zero(nx, ny);
  s.wear = Field::Zero(nx, ny);
  return s;
}

namespace {

// The state of node k (InterfaceState::classify).
NodeState node_state(const InterfaceState& s, const Field& bound, double eps, bool slipped,
                     const Field& step_slip, double slip_threshold, Eigen::Index k) {
  if (!(bound(k) > 0.0)) return NodeState::open;
  double mag = s.traction[0](k) * s.traction[0](k);
  for (std::size_t c = 1; c < s.traction.size(); ++c) mag += s.traction[c](k) * s.traction[c](k);
  mag = std::sqrt(mag);
  if (mag < bound(k) * (1.0 - eps)) return NodeState::stick;
  return slipped && step_slip(k) > slip_threshold ? NodeState::slip : NodeState::stuck_at_bound;
}

}  // namespace

// One pass, |tau| only where there is contact: the same arithmetic per node as the whole-field
// expressions it replaces (tx^2, + ty^2, sqrt), so the same states (a classify over the whole
// grid was 6 % of a full-sliding step of rough_monotone.ini, perf).
void InterfaceState::classify(const Field& bound, double eps, const Field& step_slip,
                              double slip_threshold) {
  const bool slipped = step_slip.size() == bound.size();
  for (Eigen::Index k = 0; k < bound.size(); ++k)
    state(k) = std::uint8_t(node_state(*this, bound, eps, slipped, step_slip, slip_threshold, k));
}

void InterfaceState::classify(const Field& bound, double eps, const Field& step_slip,
                              double slip_threshold, std::span<const Eigen::Index> nodes) {
  const bool slipped = step_slip.size() == bound.size();
  for (const Eigen::Index k : nodes)
    state(k) = std::uint8_t(node_state(*this, bound, eps, slipped, step_slip, slip_threshold, k));
}

}  // namespace fretbem
