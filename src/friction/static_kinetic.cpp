#include "fretbem/friction/law.hpp"

namespace fretbem {

// Kinetic nodes and their four neighbours (wrapping on a periodic grid) take mu_k.
Field StaticKineticFriction::kinetic_bound(const Field& kinetic, const Field& p) const {
  const Eigen::Index nr = kinetic.rows(), nc = kinetic.cols();
  Field front = kinetic;
  auto mark = [&](Eigen::Index i, Eigen::Index j, Eigen::Index di, Eigen::Index dj) {
    Eigen::Index a = i + di, b = j + dj;
    if (periodic_) a = (a + nr) % nr, b = (b + nc) % nc;
    if (a >= 0 && a < nr && b >= 0 && b < nc && kinetic(a, b) > 0.0) front(i, j) = 1.0;
  };
  for (Eigen::Index j = 0; j < nc; ++j)
    for (Eigen::Index i = 0; i < nr; ++i) {
      if (front(i, j) > 0.0) continue;
      mark(i, j, -1, 0), mark(i, j, 1, 0), mark(i, j, 0, -1), mark(i, j, 0, 1);
    }
  return (front > 0.0).select(mk_ * p, ms_ * p);
}

// The state of the last step says which nodes slipped (interface_state.hpp: by the step's slip).
void StaticKineticFriction::bound(const InterfaceState& s, Field& g) const {
  g = kinetic_bound((s.state == std::uint8_t(NodeState::slip)).cast<double>(), s.pressure);
}

// A node that slips within the increment is kinetic from then on: its bound and its
// neighbours' fall to mu_k p within the same increment. With mu_k only from the next step the
// nodes that start to slip in a step would carry mu_s through it, an error of the order of
// the step.
bool StaticKineticFriction::after_slip(const InterfaceState& s, const Field& slipped,
                                       Field& g) const {
  const Field last = (s.state == std::uint8_t(NodeState::slip)).cast<double>();
  const Field lower = kinetic_bound(last.max(slipped), s.pressure).min(g);
  if (!(lower < g).any()) return false;
  g = lower;
  return true;
}

}  // namespace fretbem
