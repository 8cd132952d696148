#include "fretbem/friction/law.hpp"

namespace fretbem {

std::unique_ptr<FrictionLaw> make_friction_law(const FrictionSpec& spec, double mu, bool periodic) {
  switch (spec.law) {
    case FrictionLawKind::static_kinetic:
      return std::make_unique<StaticKineticFriction>(mu, spec.mu_kinetic, periodic);
    case FrictionLawKind::evolving:
      return std::make_unique<EvolvingFriction>(mu, spec);
    case FrictionLawKind::constant:
      break;
  }
  return std::make_unique<ConstantFriction>(mu);
}

}  // namespace fretbem
