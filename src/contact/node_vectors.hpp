// Per-node vectors of the tangential operator's components (1 or 2) as fixed-size Eigen
// vectors: the per-node arithmetic of the tangential passes never allocates. Internal to
// src/contact.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include "fretbem/contact/tangential_operator.hpp"

namespace fretbem::tangential_detail {

template <int NC>
using Vec = Eigen::Matrix<double, NC, 1>;
template <int NC>
using Mat = Eigen::Matrix<double, NC, NC>;

template <int NC>
Vec<NC> at(const VecField& f, Eigen::Index k) {
  Vec<NC> v;
  for (int c = 0; c < NC; ++c) v(c) = f[c](k);
  return v;
}

template <int NC>
void put(VecField& f, Eigen::Index k, const Vec<NC>& v) {
  for (int c = 0; c < NC; ++c) f[c](k) = v(c);
}

/// The largest t >= 0 with |t0 + t d| <= g for a traction t0 inside its disc (the root of
/// |t0 + t d|^2 = g^2); infinity for d = 0.
template <int NC>
double step_to_bound(const Vec<NC>& t0, const Vec<NC>& d, double g) {
  const double dd = d.squaredNorm();
  if (!(dd > 0.0)) return std::numeric_limits<double>::infinity();
  const double td = t0.dot(d), room = std::max(0.0, g * g - t0.squaredNorm());
  return (std::sqrt(td * td + dd * room) - td) / dd;
}

/// Outcome of monotone_newton: the point reached, its mismatch |map(x) - want|, and whether
/// the last evaluation of the map was at x (the map may write state as it evaluates).
template <int NC>
struct NewtonPoint {
  Vec<NC> x;
  double mismatch = 0.0;
  bool evaluated_at_x = true;
};

/// Solves map(x) = want for a map that is the gradient of a convex function of x (its
/// Jacobian symmetric positive semi-definite), from x: Newton steps, regularised where the
/// map is flat, halved until the mismatch falls; stops at `tol`, after `iterations`, or where
/// no halving lowers the mismatch. `map(x, F, J)` sets F = map(x) and J its Jacobian.
template <int NC, class Map>
NewtonPoint<NC> monotone_newton(Map&& map, Vec<NC> x, const Vec<NC>& want, double tol,
                                int iterations) {
  Vec<NC> F, trial;
  Mat<NC> J, trial_J;
  map(x, F, J);
  NewtonPoint<NC> r{x, (F - want).norm(), true};
  for (int it = 0; it < iterations && r.mismatch > tol; ++it) {
    J += (1e-12 * J.trace() + 1e-300) * Mat<NC>::Identity();
    Vec<NC> step = J.ldlt().solve(want - F);
    int half = 0;
    for (; half < 60; ++half, step *= 0.5) {
      map(r.x + step, trial, trial_J);
      if ((trial - want).norm() < r.mismatch) break;
    }
    if (half == 60) {
      r.evaluated_at_x = false;
      break;
    }
    r.x += step, F = trial, J = trial_J;
    r.mismatch = (F - want).norm();
  }
  return r;
}

/// Calls f with the operator's component count as a compile-time constant (1 or 2).
template <class F>
decltype(auto) by_components(int nc, F&& f) {
  if (nc == 1) return f(std::integral_constant<int, 1>{});
  return f(std::integral_constant<int, 2>{});
}

}  // namespace fretbem::tangential_detail
