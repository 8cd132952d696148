#include "fretbem/wear_law/law.hpp"

namespace fretbem {

// dh = k p |s| with the pressure along the slip that the step's work takes: the worn volume is
// (k / mu) x the dissipation at a constant mu, to round-off.
Field ArchardWear::increment(const StepWork& step) const {
  return k_ * step.pressure * step.slip;
}

}  // namespace fretbem
