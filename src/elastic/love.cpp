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

}  // namespace fretbem::love
