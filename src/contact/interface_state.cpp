#include "fretbem/contact/interface_state.hpp"

namespace fretbem {

InterfaceState InterfaceState::zeros(const TangentialOperator& op) {
  const Grid& g = op.grid();
  InterfaceState s;
  s.pressure = g.zeros();
  s.traction = op.zeros();
  s.displacement = op.zeros();
  s.state = StateField::Zero(g.nx, g.ny);
  s.slip = op.zeros();
  s.slip_path = g.zeros();
  s.dissipation = g.zeros();
  s.wear = g.zeros();
  return s;
}

void InterfaceState::classify(const Field& bound, double eps, const Field& step_slip,
                              double slip_threshold) {
  Field mag = traction[0].square();
  for (std::size_t c = 1; c < traction.size(); ++c) mag += traction[c].square();
  mag = mag.sqrt();
  const bool slipped = step_slip.size() == bound.size();
  for (Eigen::Index k = 0; k < bound.size(); ++k) {
    NodeState s = NodeState::open;
    if (bound(k) > 0.0 && mag(k) < bound(k) * (1.0 - eps))
      s = NodeState::stick;
    else if (bound(k) > 0.0)
      s = slipped && step_slip(k) > slip_threshold ? NodeState::slip : NodeState::stuck_at_bound;
    state(k) = static_cast<std::uint8_t>(s);
  }
}

}  // namespace fretbem
