// Closed forms of a sphere on a flat (Hertz, Cattaneo, Mindlin): the one home of the formulas
// that preflight, the resolution report, the Python package and the tests compare against.
// SI units: forces N, lengths m, moduli and pressures Pa. E* is the contact modulus
// (1 - nu1^2)/E1 + (1 - nu2^2)/E2 inverted, G* the tangential one (Johnson, Contact
// Mechanics, 1985, eqs. 4.22 and 7.33).
#pragma once

namespace fretbem::closed_forms {

/// Hertz contact radius a (m) under normal force F (N) on a sphere of radius R (m):
/// a^3 = 3 F R / (4 E*) (Johnson eq. 4.22).
double hertz_contact_radius(double F, double R, double E_star);
/// Hertz peak pressure p0 = 3 F / (2 pi a^2) (Pa) (Johnson eq. 4.21).
double hertz_peak_pressure(double F, double a);
/// Hertz approach delta = a^2 / R (m) (Johnson eq. 4.23).
double hertz_approach(double a, double R);
/// Normal force (N) that gives contact radius a: F = 4/3 E* a^3 / R (inverse of eq. 4.22).
double hertz_force(double a, double R, double E_star);
/// Full-sliding tangential shift U* = mu delta E* / G* (m), delta the approach (m): the shift at
/// which the Cattaneo stick zone vanishes (Johnson eq. 7.42 at Q = mu P).
double full_sliding_shift(double mu, double approach, double E_star, double G_star);
/// Cattaneo stick radius over contact radius c/a = (1 - q)^(1/3), q = Q/(mu P) in [0, 1]
/// (Johnson eq. 7.41).
double cattaneo_stick_ratio(double q);
/// Cattaneo tangential shift U/U* = 1 - (1 - q)^(2/3) at force ratio q = Q/(mu P) (Johnson
/// eq. 7.42).
double cattaneo_shift_ratio(double q);
/// Inverse of cattaneo_shift_ratio: q = 1 - (1 - U/U*)^(3/2), 1 at and past full sliding.
double cattaneo_force_ratio(double shift_ratio);
/// Mindlin-Deresiewicz energy dissipated per cycle (J) under a tangential force amplitude
/// Q* = q mu P (q in [0, 1]) at constant P (N), with U* (m) the full-sliding shift:
/// W = (24/5) mu P U* [1 - (1-q)^(5/3) - (5q/6)(1 + (1-q)^(2/3))] (Johnson eq. 7.60 written
/// through U*; Mindlin & Deresiewicz 1953).
double mindlin_energy_per_cycle(double q, double mu, double P, double ustar);

}  // namespace fretbem::closed_forms
