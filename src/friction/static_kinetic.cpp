#include "fretbem/friction/law.hpp"

namespace fretbem {

// The state of the last step says which nodes slipped (interface_state.hpp: by the step's slip).
void StaticKineticFriction::bound(const InterfaceState& s, Field& g) const {
  const auto slipped = (s.state == std::uint8_t(NodeState::slip));
  g = slipped.select(mk_ * s.pressure, ms_ * s.pressure);
}

}  // namespace fretbem
