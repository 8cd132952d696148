#include "fretbem/wear/law.hpp"

namespace fretbem {

// dh = alpha |tau . s| with the end-of-step traction: the same product the stepper sums as the
// dissipated energy, so that worn volume = alpha x dissipation exactly.
Field EnergyWear::increment(const Field&, const VecField& tau, const VecField& s) const {
  Field work = tau[0] * s[0];
  for (std::size_t c = 1; c < s.size(); ++c) work += tau[c] * s[c];
  return alpha_ * work.abs();
}

}  // namespace fretbem
