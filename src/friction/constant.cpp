#include "fretbem/friction/law.hpp"

namespace fretbem {

void ConstantFriction::bound(const InterfaceState& s, Field& g) const {
  g = mu_ * s.pressure;
}

}  // namespace fretbem
