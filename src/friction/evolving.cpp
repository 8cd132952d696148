#include <cmath>

#include "fretbem/friction/law.hpp"

namespace fretbem {

void EvolvingFriction::bound(const InterfaceState& s, Field& g) const {
  const Field& x = spec_.evolution == FrictionVariable::dissipation ? s.dissipation : s.slip_path;
  const Field mu = mu0_ + (spec_.mu_final - mu0_) * (1.0 - (-x / spec_.scale).exp());
  g = mu * s.pressure;
}

double EvolvingFriction::mu(double x) const {
  return mu0_ + (spec_.mu_final - mu0_) * (1.0 - std::exp(-x / spec_.scale));
}

// The root of f(X) = X - X0 - a - b mu(X) lies in [X0 + a + b mu_min, X0 + a + b mu_max], where
// f <= 0 at the left end and >= 0 at the right (mu stays between mu_0 and mu_final, b >= 0).
// Newton steps, bisection whenever a step leaves the bracket: f' = 1 - b mu'(X) may vanish when
// a step carries X over many scales with mu rising.
double EvolvingFriction::dissipation_at_end(double x0, double a, double b) const {
  if (!(b > 0.0)) return x0 + a;
  const double base = x0 + a, lo_mu = std::min(mu0_, spec_.mu_final);
  double lo = base + b * lo_mu, hi = base + b * std::max(mu0_, spec_.mu_final);
  double x = base + b * mu(x0);
  const double dmu = spec_.mu_final - mu0_, ell = spec_.scale;
  for (int it = 0; it < 100 && hi - lo > 1e-15 * std::abs(hi); ++it) {
    const double f = x - base - b * mu(x);
    if (f == 0.0) return x;
    (f < 0.0 ? lo : hi) = x;
    const double df = 1.0 - b * dmu / ell * std::exp(-x / ell);
    const double next = df != 0.0 ? x - f / df : lo - 1.0;
    x = next > lo && next < hi ? next : 0.5 * (lo + hi);
  }
  return x;
}

// mu_1 from X_1: the slip path adds the step's |s|; the dissipation adds the step's work, whose
// end share takes mu_1 itself (X_1 = X_0 + w0 g0 |s| + mu(X_1) w1 p1 |s|: the trapezoid of the
// bound, the quadrature the stepper books the dissipation with, so the X the next step reads
// is this X_1).
void EvolvingFriction::end_bound(const InterfaceState& s, const StepSlip& step, Field& g) const {
  const bool by_work = spec_.evolution == FrictionVariable::dissipation;
  g.resize(s.pressure.rows(), s.pressure.cols());
  for (Eigen::Index k = 0; k < g.size(); ++k) {
    const double p1 = s.pressure(k);
    if (!(p1 > 0.0)) {
      g(k) = 0.0;
      continue;
    }
    const double x1 = by_work ? dissipation_at_end(s.dissipation(k), step.start_work(k),
                                                   step.end_pressure_slip(k))
                              : s.slip_path(k) + step.path(k);
    g(k) = mu(x1) * p1;
  }
}

}  // namespace fretbem
