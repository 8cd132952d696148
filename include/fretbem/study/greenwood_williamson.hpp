// Greenwood–Williamson (GW) model of partial slip (paper eqs. 2–15, 25–28): identical
// parabolic asperities of radius R, exponential height density Phi(z) = C exp(-z/lambda), each
// a Hertz–Mindlin contact (eqs. 3–10), no interaction. Closed forms as functions of
// b = d_min/lambda (eq. 5), and a direct numerical model that integrates the asperity laws over
// the height distribution to check them (docs/architecture.md "Validation ladder").
#pragma once

namespace fretbem::gw {

// ---- Closed forms (dimensionless), b = d_min / lambda >= 0 ----

/// Eq. 11: A_stick / A0 = exp(-b).
double stick_area_ratio(double b);
/// Eq. 14: F_x / (mu F_z) = 1 - exp(-b).
double force_ratio(double b);
/// Eq. 27: F_stick / (mu F_z) = exp(-b) (2 sqrt(b/pi) - 1) + erfc(sqrt(b)).
double stick_force_ratio(double b);
/// Eq. 28: F_slip / (mu F_z) = 1 - 2 exp(-b) sqrt(b/pi) - erfc(sqrt(b)).
double slip_force_ratio(double b);
/// Inverse of eq. 14: b for a force ratio f = F_x/(mu F_z) in [0, 1).
double b_of_force_ratio(double f);
/// Eq. 26 (GW, nominally flat): k_x / k_x0 = 1 - f.
double stiffness_ratio_flat(double f);
/// Eq. 25 (fractal, no roll-off): k_x / k_x0 = (1 - f)^(1/(1+H)).
double stiffness_ratio_fractal(double f, double hurst);
/// Eq. 5: depth below which an asperity slides fully, d_min = u_x G* / (mu E*).
double d_min(double ux, double mu, double E_star, double G_star);

// ---- Direct numerical GW model ----

struct Params {
  double E_star = 1.0;   ///< reduced modulus (Pa)
  double G_star = 1.0;   ///< reduced shear modulus (Pa), paper's G* = 4G/(2 - nu)
  double mu = 0.5;       ///< Coulomb friction coefficient
  double R = 1.0;        ///< asperity radius (m)
  double lambda = 1.0;   ///< height scale of the exponential density (m)
  double density = 1.0;  ///< C: asperities per unit height (1/m), per nominal area
  double h = 0.0;        ///< separation: asperities with z > h touch, depth d = z - h
};

/// Totals of the asperity ensemble at tangential displacement u_x (monotone loading from 0).
struct State {
  double Fz = 0, A0 = 0;  ///< normal force (eq. 6 summed), contact area
  double Fx = 0;          ///< tangential force (eqs. 7, 9 summed)
  double A_stick = 0;     ///< stick area (eq. 8 summed)
  double F_stick = 0;     ///< force carried inside the stick circles
  double F_slip = 0;      ///< force carried by slip annuli and fully sliding asperities
  double kx = 0;          ///< differential tangential stiffness dF_x/du_x
};

/// Integrates the Hertz–Mindlin asperity laws over Phi by composite Gauss–Legendre after the
/// substitutions d = s^2 on [0, d_min] and d = d_min + t^2 on [d_min, inf), which remove the
/// square-root singularities of the 3/2-power laws at d = 0 and d = d_min.
State numerical(const Params& p, double ux);

}  // namespace fretbem::gw
