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

// One pass, |tau| only where there is contact: the same arithmetic per node as the whole-field
// expressions it replaces (tx^2, + ty^2, sqrt), so the same states (a classify over the whole
// grid was 6 % of a full-sliding step of rough_monotone.ini, perf).
void InterfaceState::classify(const Field& bound, double eps, const Field& step_slip,
                              double slip_threshold) {
  const bool slipped = step_slip.size() == bound.size();
  const std::size_t nc = traction.size();
  for (Eigen::Index k = 0; k < bound.size(); ++k) {
    NodeState s = NodeState::open;
    if (bound(k) > 0.0) {
      double mag = traction[0](k) * traction[0](k);
      for (std::size_t c = 1; c < nc; ++c) mag += traction[c](k) * traction[c](k);
      mag = std::sqrt(mag);
      if (mag < bound(k) * (1.0 - eps))
        s = NodeState::stick;
      else
        s = slipped && step_slip(k) > slip_threshold ? NodeState::slip : NodeState::stuck_at_bound;
    }
    state(k) = static_cast<std::uint8_t>(s);
  }
}

}  // namespace fretbem
