#include "fretbem/elastic/love.hpp"

#include <cmath>

namespace fretbem::love {

namespace {

// X asinh(Y/|X|), continuous with value 0 at X = 0.
double xasinh(double X, double Y) {
  return X == 0.0 ? 0.0 : X * std::asinh(Y / std::fabs(X));
}

// Corner sum over the cell: F(x+a, y+b) - F(x+a, y-b) - F(x-a, y+b) + F(x-a, y-b), with
// X = x - x' running over [x-a, x+a] as x' runs over the cell.
template <class F>
double corner_sum(F f, double x, double y, double a, double b) {
  return f(x + a, y + b) - f(x + a, y - b) - f(x - a, y + b) + f(x - a, y - b);
}

// X atan(Y/X) + (Y/2) ln(X^2 + Y^2): d2/dXdY of it is X / (X^2 + Y^2). Both terms vanish
// continuously on X = 0 and at the origin (|X atan| <= pi |X| / 2, Y ln Y -> 0).
double xatan_ylog(double X, double Y) {
  const double r2 = X * X + Y * Y;
  const double a = X == 0.0 ? 0.0 : X * std::atan(Y / X);
  const double b = Y == 0.0 ? 0.0 : 0.5 * Y * std::log(r2);
  return a + b;
}

}  // namespace

double I1(double x, double y, double a, double b) {
  return corner_sum([](double X, double Y) { return xasinh(X, Y) + xasinh(Y, X); }, x, y, a, b);
}

double Ixx(double x, double y, double a, double b) {
  return corner_sum([](double X, double Y) { return xasinh(Y, X); }, x, y, a, b);
}

double Iyy(double x, double y, double a, double b) {
  return corner_sum([](double X, double Y) { return xasinh(X, Y); }, x, y, a, b);
}

double Ixy(double x, double y, double a, double b) {
  return corner_sum([](double X, double Y) { return -std::hypot(X, Y); }, x, y, a, b);
}

double Jx(double x, double y, double a, double b) {
  return corner_sum([](double X, double Y) { return xatan_ylog(X, Y); }, x, y, a, b);
}

double Jy(double x, double y, double a, double b) {
  return Jx(y, x, b, a);
}

}  // namespace fretbem::love
