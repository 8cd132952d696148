// A linearisation point of the implicit wear integrator's Newton matrix that the tests share:
// a Hertz-like contact disc with wear in its outer annulus and a random right-hand side.
// Header-only: each test executable includes it once.
#pragma once

#include <cmath>
#include <random>

#include "fretbem/elastic/grid.hpp"

namespace fretbem_test {

using namespace fretbem;

struct WornDisc {
  Field pressure;        ///< Pa
  Field wear_per_cycle;  ///< m per cycle
  Field rhs;             ///< uniform in [-0.5, 0.5)
};

/// A disc of contact of radius 40 um (peak pressure 1 GPa); wear per cycle k p S (k = 5e-14
/// 1/Pa) with S up to 0.2 um in the annulus 0.4 < (r/a)^2 < 1, so that gamma d / C(0,0) spans
/// 0 ... ~10^2 for gamma = 0 ... 1e5 cycles on a 0.1 mm grid.
inline WornDisc worn_disc(const Grid& g) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  WornDisc d{g.zeros(), g.zeros(), Field(g.nx, g.ny)};
  for (int i = 0; i < g.nx; ++i)
    for (int j = 0; j < g.ny; ++j) {
      const double r2 = (g.x(i) * g.x(i) + g.y(j) * g.y(j)) / (4e-5 * 4e-5);
      if (r2 < 1.0) d.pressure(i, j) = 1e9 * std::sqrt(1.0 - r2);
      if (r2 > 0.4 && r2 < 1.0) d.wear_per_cycle(i, j) = 5e-14 * d.pressure(i, j) * 2e-7 * r2;
      d.rhs(i, j) = uni(rng) - 0.5;
    }
  return d;
}

}  // namespace fretbem_test
