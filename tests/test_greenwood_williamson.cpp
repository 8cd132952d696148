// Greenwood–Williamson partial slip (docs/architecture.md, validation ladder): the paper's closed
// forms (eqs. 11, 13–15, 27, 28; stiffness eq. 26) against the direct sum of Hertz–Mindlin
// asperities over an exponential height density, plus limits and the force split.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "fretbem/core/errors.hpp"
#include "fretbem/study/greenwood_williamson.hpp"

using namespace fretbem;

namespace {

// Steel-like moduli, nu = 0.3: E* = E/(1 - nu^2), G* = 4G/(2 - nu) (paper, after eq. 3).
gw::Params steel() {
  gw::Params p;
  const double E = 210e9, nu = 0.3, G = E / (2 * (1 + nu));
  p.E_star = E / (1 - nu * nu);
  p.G_star = 4 * G / (2 - nu);
  p.mu = 0.4;
  p.R = 50e-6;
  p.lambda = 0.3e-6;
  p.density = 1e9 / p.lambda;  // arbitrary: every ratio below is independent of it
  p.h = 0.7e-6;
  return p;
}

double b_of(const gw::Params& p, double ux) {
  return gw::d_min(ux, p.mu, p.E_star, p.G_star) / p.lambda;
}

// The quadrature (composite 16-point Gauss–Legendre on smooth integrands after the square-root
// substitutions) is accurate to ~1e-13; the requirement is 1e-3. We check 1e-9: far inside the
// requirement, far above round-off, so a wrong law (not a slightly inaccurate rule) fails.
constexpr double kTol = 1e-9;

const double kBs[] = {0.0, 1e-4, 0.01, 0.1, 0.5, 1.0, 2.0, 4.0, 8.0};

}  // namespace

TEST(GreenwoodWilliamson, NormalForceIsEq13) {
  // Eq. 13: F_z = (4/3) E* sqrt(R) C e^{-h/lambda} Gamma(5/2) lambda^{5/2}; eq. 11's A0 =
  // pi R C e^{-h/lambda} lambda^2.
  const gw::Params p = steel();
  const gw::State s = gw::numerical(p, 0.0);
  const double ce = p.density * std::exp(-p.h / p.lambda);
  const double Fz =
      4.0 / 3.0 * p.E_star * std::sqrt(p.R) * ce * std::tgamma(2.5) * std::pow(p.lambda, 2.5);
  const double A0 = std::numbers::pi * p.R * ce * p.lambda * p.lambda;
  EXPECT_NEAR(s.Fz / Fz, 1.0, kTol);
  EXPECT_NEAR(s.A0 / A0, 1.0, kTol);
  EXPECT_NEAR(s.A_stick / A0, 1.0, kTol);  // no displacement: everything sticks
  EXPECT_EQ(s.Fx, 0.0);
}

TEST(GreenwoodWilliamson, ClosedFormsMatchTheAsperitySum) {
  const gw::Params p = steel();
  const gw::State s0 = gw::numerical(p, 0.0);
  for (double b : kBs) {
    const double ux = b * p.lambda * p.mu * p.E_star / p.G_star;  // inverse of eq. 5
    ASSERT_NEAR(b_of(p, ux), b, 1e-12 * (1 + b));
    const gw::State s = gw::numerical(p, ux);
    const double muFz = p.mu * s.Fz;
    EXPECT_NEAR(s.Fz / s0.Fz, 1.0, kTol) << "constant normal load";
    EXPECT_NEAR(s.A_stick / s.A0, gw::stick_area_ratio(b), kTol) << "eq. 11, b = " << b;
    EXPECT_NEAR(s.Fx / muFz, gw::force_ratio(b), kTol) << "eq. 14, b = " << b;
    EXPECT_NEAR(s.F_stick / muFz, gw::stick_force_ratio(b), kTol) << "eq. 27, b = " << b;
    EXPECT_NEAR(s.F_slip / muFz, gw::slip_force_ratio(b), kTol) << "eq. 28, b = " << b;
    EXPECT_NEAR(s.kx / s0.kx, gw::stiffness_ratio_flat(gw::force_ratio(b)), kTol)
        << "eq. 26, b = " << b;
    // Eq. 15: F_x/F_x,max = 1 - A_stick/A0 = A_slip/A0.
    EXPECT_NEAR(s.Fx / muFz, 1.0 - s.A_stick / s.A0, kTol) << "eq. 15, b = " << b;
  }
}

TEST(GreenwoodWilliamson, StickPlusSlipIsTheTotalForce) {
  // The numerical stick and slip forces are integrated separately (stick circles vs annuli and
  // fully sliding asperities), so their sum equal to F_x is a real check.
  const gw::Params p = steel();
  for (double b : kBs) {
    const gw::State s = gw::numerical(p, b * p.lambda * p.mu * p.E_star / p.G_star);
    EXPECT_NEAR((s.F_stick + s.F_slip) / (p.mu * s.Fz), s.Fx / (p.mu * s.Fz), 1e-12);
    EXPECT_NEAR(gw::stick_force_ratio(b) + gw::slip_force_ratio(b), gw::force_ratio(b), 1e-14);
  }
}

TEST(GreenwoodWilliamson, StiffnessIsTheDerivativeOfTheForce) {
  // k_x from the per-asperity law 2 G* c vs a central difference of the integrated F_x(u_x).
  const gw::Params p = steel();
  const double u1 = p.lambda * p.mu * p.E_star / p.G_star;  // b = 1
  const double du = 1e-4 * u1;
  const double fd = (gw::numerical(p, u1 + du).Fx - gw::numerical(p, u1 - du).Fx) / (2 * du);
  // Central difference error ~ du^2 F'''/6 ~ 1e-8 relative; round-off ~ 1e-16/1e-4.
  EXPECT_NEAR(fd / gw::numerical(p, u1).kx, 1.0, 1e-7);
}

TEST(GreenwoodWilliamson, LiteralEquationsAgreeWithTheStableForms) {
  // Eqs. 27 and 28 as printed in the paper, where they do not cancel catastrophically.
  for (double b : {0.05, 0.3, 1.0, 3.0, 10.0}) {
    const double eb = std::exp(-b), sb = std::sqrt(b / std::numbers::pi);
    EXPECT_NEAR(gw::stick_force_ratio(b), eb * (2 * sb - 1) + std::erfc(std::sqrt(b)), 1e-14);
    EXPECT_NEAR(gw::slip_force_ratio(b), 1 - 2 * eb * sb - std::erfc(std::sqrt(b)), 1e-14);
  }
}

TEST(GreenwoodWilliamson, Limits) {
  // b -> 0: everything sticks, F_stick/F_x -> 1 with F_slip ~ (4/3) b^{3/2}/sqrt(pi) (series of
  // P(3/2, b)); b -> inf: full sliding, F_stick -> 0, F_slip -> mu F_z, A_stick -> 0.
  for (double b : {1e-10, 1e-7, 1e-4}) {
    EXPECT_NEAR(gw::stick_force_ratio(b) / gw::force_ratio(b), 1.0, 2 * std::sqrt(b));
    EXPECT_NEAR(
        gw::slip_force_ratio(b) / (4.0 / 3.0 * std::pow(b, 1.5) / std::sqrt(std::numbers::pi)), 1.0,
        2 * b);
  }
  EXPECT_EQ(gw::stick_force_ratio(0.0), 0.0);
  EXPECT_EQ(gw::stick_area_ratio(0.0), 1.0);
  for (double b : {30.0, 60.0}) {
    EXPECT_LT(gw::stick_force_ratio(b), 1e-11);
    EXPECT_NEAR(gw::slip_force_ratio(b), 1.0, 1e-11);
    EXPECT_NEAR(gw::force_ratio(b), 1.0, 1e-11);
    EXPECT_LT(gw::stick_area_ratio(b), 1e-11);
  }
  // Bell shape: F_stick/(mu F_z) rises from 0, peaks, and falls back to 0 (paper Fig. 4).
  double peak = 0, bpeak = 0;
  for (double b = 0.0; b < 20; b += 0.001)
    if (gw::stick_force_ratio(b) > peak) peak = gw::stick_force_ratio(b), bpeak = b;
  EXPECT_GT(bpeak, 0.1);
  EXPECT_LT(bpeak, 5.0);
}

TEST(GreenwoodWilliamson, StiffnessLaws) {
  EXPECT_DOUBLE_EQ(gw::stiffness_ratio_flat(0.25), 0.75);
  EXPECT_DOUBLE_EQ(gw::stiffness_ratio_fractal(0.75, 1.0), 0.5);  // (1/4)^(1/2)
  EXPECT_NEAR(gw::b_of_force_ratio(gw::force_ratio(1.7)), 1.7, 1e-14);
  EXPECT_THROW(gw::b_of_force_ratio(1.0), InputError);
  EXPECT_THROW(gw::stick_area_ratio(-1.0), InputError);
}
