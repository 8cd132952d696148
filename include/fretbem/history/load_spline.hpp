// The smooth interpolation of a load table (load.interpolation = cubic): a not-a-knot cubic
// spline through the rows, column by column, kept as its slope at every row, and the cubic
// Hermite form that evaluates it within a row from the slopes at the row's two ends.
#pragma once

#include <vector>

namespace fretbem {

/// The slopes dy/dt at the knots t (strictly increasing) of the C2 cubic spline through
/// (t, y) with not-a-knot ends: the third derivative is continuous at the second and the
/// last but one knot, so the spline reproduces any cubic exactly and has an error of order
/// h^4 up to the ends. Two knots: the line; three: the parabola through them.
std::vector<double> not_a_knot_slopes(const std::vector<double>& t, const std::vector<double>& y);

/// The cubic on [t0, t0 + h] with values y0, y1 and slopes m0, m1 at its ends, at the
/// fraction theta in [0, 1] of the interval (cubic Hermite form).
double hermite(double y0, double m0, double y1, double m1, double h, double theta);
/// Its slope d/dt there.
double hermite_slope(double y0, double m0, double y1, double m1, double h, double theta);
/// Its least value on the interval (at an end or where its slope vanishes).
double hermite_minimum(double y0, double m0, double y1, double m1, double h);

}  // namespace fretbem
