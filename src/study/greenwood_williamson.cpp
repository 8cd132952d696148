#include "fretbem/study/greenwood_williamson.hpp"

#include <boost/math/quadrature/gauss.hpp>
#include <boost/math/special_functions/gamma.hpp>
#include <cmath>
#include <numbers>

#include "fretbem/core/errors.hpp"

namespace fretbem::gw {

namespace {

constexpr double kPi = std::numbers::pi;

void check_b(double b) {
  if (!(b >= 0.0)) throw InputError("GW: b = d_min/lambda must be >= 0, got " + std::to_string(b));
}

// f = F_x/(mu F_z) of a stiffness ratio: up to full sliding (f = 1, zero stiffness). Beyond it
// the fractal ratio is NaN and the flat one negative.
void check_f(double f) {
  if (!(f >= 0.0 && f <= 1.0))
    throw InputError("GW: F_x/(mu F_z) must be in [0, 1], got " + std::to_string(f));
}

}  // namespace

double stick_area_ratio(double b) {
  return check_b(b), std::exp(-b);
}

double force_ratio(double b) {
  return check_b(b), -std::expm1(-b);
}

// Eq. 27 rewritten without cancellation: erf(sqrt b) - 2 sqrt(b/pi) e^-b is the regularised
// lower incomplete gamma P(3/2, b), so F_stick/(mu F_z) = (1 - e^-b) - P(3/2, b), i.e. eq. 14
// minus eq. 28. The literal form loses all digits as b -> 0 (1 - erfc and 2 sqrt(b/pi) cancel).
double stick_force_ratio(double b) {
  check_b(b);
  return -std::expm1(-b) - boost::math::gamma_p(1.5, b);
}

// Eq. 28 = P(3/2, b) (see above).
double slip_force_ratio(double b) {
  check_b(b);
  return boost::math::gamma_p(1.5, b);
}

double b_of_force_ratio(double f) {
  if (!(f >= 0.0 && f < 1.0))
    throw InputError("GW: F_x/(mu F_z) must be in [0, 1), got " + std::to_string(f));
  return -std::log1p(-f);
}

double stiffness_ratio_flat(double f) {
  return check_f(f), 1.0 - f;
}

double stiffness_ratio_fractal(double f, double hurst) {
  check_f(f);
  if (!(hurst > 0.0 && hurst <= 1.0))
    throw InputError("GW: the Hurst exponent must be in (0, 1], got " + std::to_string(hurst));
  return std::pow(1.0 - f, 1.0 / (1.0 + hurst));
}

double d_min(double ux, double mu, double E_star, double G_star) {
  return ux * G_star / (mu * E_star);
}

namespace {

// Composite 16-point Gauss–Legendre of f on [a, b] with `panels` equal panels; f adds into
// State. Boost tabulates the rule's non-negative abscissae and their weights (the rule is
// symmetric about 0; an abscissa at 0 counts once).
template <class F>
void integrate(double a, double b, int panels, F&& f) {
  using Rule = boost::math::quadrature::gauss<double, 16>;
  const auto& x = Rule::abscissa();
  const auto& w = Rule::weights();
  const double hp = (b - a) / panels, half = 0.5 * hp;
  for (int k = 0; k < panels; ++k) {
    const double mid = a + hp * (k + 0.5);
    for (std::size_t i = 0; i < x.size(); ++i) {
      f(mid - half * x[i], half * w[i]);
      if (x[i] != 0.0) f(mid + half * x[i], half * w[i]);
    }
  }
}

// Per-asperity laws at depth d (Hertz, eq. 6; Mindlin, eqs. 7–10) with weight wt = Phi dz.
// Stick force: Cattaneo's traction mu (p_H(a) - p_H(c)) integrated over r < c, with
// int_0^c p_H(a) 2 pi r dr = (4E*/3R) (a^3 - (a^2 - c^2)^{3/2}) and a^2 - c^2 = R d_min:
// F_stick0 = mu (4/3) E* sqrt(R) (d^{3/2} - d_min^{3/2} - (d - d_min)^{3/2}). The slip annulus
// carries mu p_H(a) over c < r < a: mu (4/3) E* sqrt(R) d_min^{3/2}. k_x0 = dF_x0/du_x =
// 2 G* sqrt(R (d - d_min)) = 2 G* c.
void add_asperity(const Params& p, double dm, double d, double wt, State& s) {
  const double hz = 4.0 / 3.0 * p.E_star * std::sqrt(p.R);
  const double fz = hz * std::pow(d, 1.5);
  s.Fz += fz * wt;
  s.A0 += kPi * p.R * d * wt;
  if (d <= dm) {  // full sliding (eqs. 9, 10)
    s.Fx += p.mu * fz * wt;
    s.F_slip += p.mu * fz * wt;
    return;
  }
  const double e = d - dm;
  s.Fx += p.mu * hz * (std::pow(d, 1.5) - std::pow(e, 1.5)) * wt;
  s.A_stick += kPi * p.R * e * wt;
  s.F_stick += p.mu * hz * (std::pow(d, 1.5) - std::pow(dm, 1.5) - std::pow(e, 1.5)) * wt;
  s.F_slip += p.mu * hz * std::pow(dm, 1.5) * wt;
  s.kx += 2.0 * p.G_star * std::sqrt(p.R * e) * wt;
}

}  // namespace

State numerical(const Params& p, double ux) {
  if (!(p.E_star > 0 && p.G_star > 0 && p.mu > 0 && p.R > 0 && p.lambda > 0 && p.density > 0))
    throw InputError("GW: moduli, mu, R, lambda and density must be > 0");
  if (!(ux >= 0.0)) throw InputError("GW: u_x must be >= 0, got " + std::to_string(ux));
  const double dm = d_min(ux, p.mu, p.E_star, p.G_star);
  auto phi = [&](double d) { return p.density * std::exp(-(d + p.h) / p.lambda); };
  State s;
  // [0, d_min]: d = s^2, dd = 2 s ds.
  if (dm > 0.0)
    integrate(0.0, std::sqrt(dm), 64,
              [&](double x, double w) { add_asperity(p, dm, x * x, phi(x * x) * 2.0 * x * w, s); });
  // [d_min, inf): d = d_min + t^2; the weight exp(-t^2/lambda) is below e^-200 past t_max.
  const double tmax = std::sqrt(200.0 * p.lambda);
  integrate(0.0, tmax, 256, [&](double t, double w) {
    const double d = dm + t * t;
    add_asperity(p, dm, d, phi(d) * 2.0 * t * w, s);
  });
  return s;
}

}  // namespace fretbem::gw
