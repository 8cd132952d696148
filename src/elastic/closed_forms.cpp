// Hertz, Cattaneo and Mindlin closed forms. The operation order of each expression is the one
// the run paths evaluated, so every output that depends on them stays bit-identical.
#include "fretbem/elastic/closed_forms.hpp"

#include <cmath>
#include <numbers>

namespace fretbem::closed_forms {

double hertz_contact_radius(double F, double R, double E_star) {
  return std::cbrt(3.0 * F * R / (4.0 * E_star));
}

double hertz_peak_pressure(double F, double a) {
  return 3.0 * F / (2.0 * std::numbers::pi * a * a);
}

double hertz_approach(double a, double R) {
  return a * a / R;
}

double hertz_force(double a, double R, double E_star) {
  return 4.0 / 3.0 * E_star * a * a * a / R;
}

double full_sliding_shift(double mu, double approach, double E_star, double G_star) {
  return mu * approach * E_star / G_star;
}

double cattaneo_stick_ratio(double q) {
  return std::cbrt(1 - q);
}

double cattaneo_shift_ratio(double q) {
  return 1 - std::pow(1 - q, 2.0 / 3.0);
}

double cattaneo_force_ratio(double shift_ratio) {
  return shift_ratio >= 1 ? 1.0 : 1 - std::pow(1 - shift_ratio, 1.5);
}

double mindlin_energy_per_cycle(double q, double mu, double P, double ustar) {
  return 24.0 / 5.0 * mu * P * ustar *
         (1 - std::pow(1 - q, 5.0 / 3) - 5 * q / 6 * (1 + std::pow(1 - q, 2.0 / 3)));
}

}  // namespace fretbem::closed_forms
