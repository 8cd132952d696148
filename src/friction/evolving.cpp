#include "fretbem/friction/law.hpp"

namespace fretbem {

void EvolvingFriction::bound(const InterfaceState& s, Field& g) const {
  const Field& x = spec_.evolution == FrictionVariable::dissipation ? s.dissipation : s.slip_path;
  const Field mu = mu0_ + (spec_.mu_final - mu0_) * (1.0 - (-x / spec_.scale).exp());
  g = mu * s.pressure;
}

}  // namespace fretbem
