// Love's influence coefficients: closed-form integrals of the half-space Green's functions over
// one uniformly loaded rectangular cell (Love 1929; Johnson, Contact Mechanics, §3.9, eq. 3.25).
#pragma once

namespace fretbem::love {

/// Integral of 1/r over the cell |x'| <= a, |y'| <= b, evaluated at (x, y) (units of length).
/// Antiderivative F(X,Y) = X asinh(Y/|X|) + Y asinh(X/|Y|): the absolute values make F odd in
/// X and in Y, which the corner sum needs at mixed-sign corner offsets.
double I1(double x, double y, double a, double b);
/// Integral of x^2/r^3 over the same cell (antiderivative Y asinh(X/|Y|)).
double Ixx(double x, double y, double a, double b);
/// Integral of y^2/r^3 over the same cell (antiderivative X asinh(Y/|X|)).
double Iyy(double x, double y, double a, double b);
/// Integral of x y/r^3 over the same cell (antiderivative -r).
double Ixy(double x, double y, double a, double b);
/// Integral of x/r^2 over the same cell (units of length): the Boussinesq–Cerruti cross term
/// (normal-tangential coupling, Johnson eqs. 3.19a, 3.86c). Antiderivative
/// X atan(Y/X) + (Y/2) ln(X^2 + Y^2); odd in x, even in y.
double Jx(double x, double y, double a, double b);
/// Integral of y/r^2 over the same cell: Jx with the axes exchanged.
double Jy(double x, double y, double a, double b);

}  // namespace fretbem::love
