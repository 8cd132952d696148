#include "fretbem/wear/law.hpp"

namespace fretbem {

// dh = k p |s|: p is the step's pressure (constant over the step: the normal load and the
// surface change only between steps), |s| the slip length of the step.
Field ArchardWear::increment(const Field& p, const VecField&, const VecField& s) const {
  Field len2 = s[0].square();
  for (std::size_t c = 1; c < s.size(); ++c) len2 += s[c].square();
  return k_ * p * len2.sqrt();
}

}  // namespace fretbem
