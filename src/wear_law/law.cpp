#include "fretbem/wear_law/law.hpp"

namespace fretbem {

std::unique_ptr<WearModel> make_wear_model(const WearSpec& spec) {
  switch (spec.law) {
    case WearLaw::archard:
      return std::make_unique<ArchardWear>(spec.coefficient);
    case WearLaw::energy:
      return std::make_unique<EnergyWear>(spec.coefficient);
    case WearLaw::none:
      break;
  }
  return nullptr;
}

}  // namespace fretbem
