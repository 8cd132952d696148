// The closed-form module against exact identities and an independent quadrature of the
// Mindlin-Deresiewicz hysteresis loop (Johnson, Contact Mechanics, §§4.2, 7.4-7.5).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "fretbem/elastic/closed_forms.hpp"

namespace cf = fretbem::closed_forms;

// Hertz: the force of radius a recovers a; the mean pressure over pi a^2 is (2/3) p0.
TEST(ClosedForms, HertzRadiusForceAndPressureAreConsistent) {
  const double E_star = 210e9 / (1 - 0.09), R = 0.01, F = 10;
  const double a = cf::hertz_contact_radius(F, R, E_star);
  EXPECT_NEAR(cf::hertz_force(a, R, E_star), F, 1e-12 * F);
  EXPECT_NEAR(F / (std::numbers::pi * a * a), 2.0 / 3.0 * cf::hertz_peak_pressure(F, a),
              1e-12 * cf::hertz_peak_pressure(F, a));
  EXPECT_DOUBLE_EQ(cf::hertz_approach(a, R), a * a / R);
}

// Cattaneo: the force ratio inverts the shift ratio; full sliding at U = U*; c/a = 0 at q = 1.
TEST(ClosedForms, CattaneoShiftAndForceRatiosAreInverse) {
  for (double q : {0.0, 0.1, 0.5, 0.9, 0.999})
    EXPECT_NEAR(cf::cattaneo_force_ratio(cf::cattaneo_shift_ratio(q)), q, 1e-12) << q;
  EXPECT_EQ(cf::cattaneo_force_ratio(1.0), 1.0);
  EXPECT_EQ(cf::cattaneo_force_ratio(2.0), 1.0);
  EXPECT_EQ(cf::cattaneo_stick_ratio(1.0), 0.0);
  EXPECT_NEAR(cf::cattaneo_stick_ratio(0.875), 0.5, 1e-15);
}

// Mindlin-Deresiewicz: the energy per cycle equals the area between the Masing unloading and
// reloading branches U(Q) (Johnson eq. 7.58), integrated by the midpoint rule in Q (error O(1/n^2);
// n = 20000 gives ~1e-9 relative away from q = 1, where f' is singular at the loop tips).
TEST(ClosedForms, MindlinEnergyIsTheMasingLoopArea) {
  const double mu = 0.5, P = 2.0, ustar = 3e-6, muP = mu * P;
  auto f = [&](double Q) { return ustar * cf::cattaneo_shift_ratio(Q / muP); };
  for (double q : {0.2, 0.5, 0.8}) {
    const double Qa = q * muP;
    const int n = 20000;
    double area = 0;
    for (int k = 0; k < n; ++k) {
      const double Q = -Qa + (k + 0.5) * 2 * Qa / n;
      const double unload = f(Qa) - 2 * f((Qa - Q) / 2), reload = -f(Qa) + 2 * f((Qa + Q) / 2);
      area += (unload - reload) * 2 * Qa / n;  // the unloading branch lies at larger U
    }
    const double W = cf::mindlin_energy_per_cycle(q, mu, P, ustar);
    EXPECT_NEAR(W, area, 1e-6 * W) << q;
  }
  // At q = 1 the bracket is 1 - 5/6: W = (4/5) mu P U*.
  EXPECT_NEAR(cf::mindlin_energy_per_cycle(1.0, mu, P, ustar), 0.8 * muP * ustar, 1e-15);
}

// U* = mu delta E*/G* scales linearly in each factor.
TEST(ClosedForms, FullSlidingShiftIsMuDeltaEOverG) {
  EXPECT_DOUBLE_EQ(cf::full_sliding_shift(0.5, 2e-6, 3.0, 1.5), 2e-6);
}
