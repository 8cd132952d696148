#include "fretbem/wear_law/law.hpp"

namespace fretbem {

// dh = alpha x the step's frictional work, the product the stepper sums as the dissipated
// energy: worn volume = alpha x dissipation exactly.
Field EnergyWear::increment(const StepWork& step) const {
  return alpha_ * step.work;
}

}  // namespace fretbem
