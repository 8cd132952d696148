// Not-a-knot slopes by the tridiagonal system of C2 continuity at the interior knots, closed
// by the not-a-knot conditions at both ends (de Boor, A Practical Guide to Splines, ch. IV;
// the end rows as in Moler, Numerical Computing with MATLAB, splinetx), solved by elimination
// without pivoting (the interior rows are diagonally dominant).
#include "fretbem/history/load_spline.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace fretbem {

namespace {

// The parabola through three knots, its slope at each.
std::vector<double> parabola_slopes(const std::vector<double>& t, const std::vector<double>& y) {
  const double h0 = t[1] - t[0], h1 = t[2] - t[1];
  const double d0 = (y[1] - y[0]) / h0, d1 = (y[2] - y[1]) / h1;
  const double curvature = (d1 - d0) / (h0 + h1);  // half the second derivative
  return {d0 - curvature * h0, d0 + curvature * h0, d1 + curvature * h1};
}

// Solves sub[i] x[i-1] + diag[i] x[i] + super[i] x[i+1] = rhs[i] (Thomas algorithm).
std::vector<double> solve_tridiagonal(std::vector<double> sub, std::vector<double> diag,
                                      std::vector<double> super, std::vector<double> rhs) {
  const std::size_t n = diag.size();
  for (std::size_t i = 1; i < n; ++i) {
    const double f = sub[i] / diag[i - 1];
    diag[i] -= f * super[i - 1];
    rhs[i] -= f * rhs[i - 1];
  }
  std::vector<double> x(n);
  x[n - 1] = rhs[n - 1] / diag[n - 1];
  for (std::size_t i = n - 1; i-- > 0;) x[i] = (rhs[i] - super[i] * x[i + 1]) / diag[i];
  return x;
}

}  // namespace

std::vector<double> not_a_knot_slopes(const std::vector<double>& t, const std::vector<double>& y) {
  const std::size_t n = t.size();
  if (n < 2) return std::vector<double>(n, 0.0);
  if (n == 2) return std::vector<double>(2, (y[1] - y[0]) / (t[1] - t[0]));
  if (n == 3) return parabola_slopes(t, y);
  std::vector<double> h(n - 1), d(n - 1);
  for (std::size_t i = 0; i + 1 < n; ++i) h[i] = t[i + 1] - t[i], d[i] = (y[i + 1] - y[i]) / h[i];
  std::vector<double> sub(n, 0.0), diag(n), super(n, 0.0), rhs(n);
  // Row 0: the third derivative continuous at knot 1, with knot 1's row used to drop m2.
  diag[0] = h[1], super[0] = h[0] + h[1];
  rhs[0] = ((h[0] + 2 * super[0]) * h[1] * d[0] + h[0] * h[0] * d[1]) / super[0];
  for (std::size_t i = 1; i + 1 < n; ++i) {  // C2 at knot i
    sub[i] = h[i], diag[i] = 2 * (h[i - 1] + h[i]), super[i] = h[i - 1];
    rhs[i] = 3 * (h[i] * d[i - 1] + h[i - 1] * d[i]);
  }
  const double a = h[n - 3] + h[n - 2];  // the mirror of row 0 at the last knot
  sub[n - 1] = a, diag[n - 1] = h[n - 3];
  rhs[n - 1] = (h[n - 2] * h[n - 2] * d[n - 3] + (2 * a + h[n - 2]) * h[n - 3] * d[n - 2]) / a;
  return solve_tridiagonal(sub, diag, super, rhs);
}

double hermite(double y0, double m0, double y1, double m1, double h, double theta) {
  const double s = theta, s2 = s * s, s3 = s2 * s;
  return (2 * s3 - 3 * s2 + 1) * y0 + (s3 - 2 * s2 + s) * h * m0 + (3 * s2 - 2 * s3) * y1 +
         (s3 - s2) * h * m1;
}

double hermite_slope(double y0, double m0, double y1, double m1, double h, double theta) {
  const double s = theta, s2 = s * s;
  return ((6 * s2 - 6 * s) * (y0 - y1)) / h + (3 * s2 - 4 * s + 1) * m0 + (3 * s2 - 2 * s) * m1;
}

// The slope in theta is a theta^2 + b theta + c; its zeros in (0, 1) are the interior extrema.
double hermite_minimum(double y0, double m0, double y1, double m1, double h) {
  const double a = 6 * (y0 - y1) + 3 * h * (m0 + m1), b = -6 * (y0 - y1) - h * (4 * m0 + 2 * m1),
               c = h * m0;
  double least = std::min(y0, y1);
  auto consider = [&](double s) {
    if (s > 0.0 && s < 1.0) least = std::min(least, hermite(y0, m0, y1, m1, h, s));
  };
  if (a == 0.0) {
    if (b != 0.0) consider(-c / b);
    return least;
  }
  const double disc = b * b - 4 * a * c;
  if (disc < 0.0) return least;
  consider((-b + std::sqrt(disc)) / (2 * a));
  consider((-b - std::sqrt(disc)) / (2 * a));
  return least;
}

}  // namespace fretbem
