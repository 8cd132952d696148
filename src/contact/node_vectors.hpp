// Per-node vectors of the tangential operator's components (1 or 2) as fixed-size Eigen
// vectors: the per-node arithmetic of the tangential passes never allocates. Internal to
// src/contact.
#pragma once

#include <Eigen/Core>
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

/// Calls f with the operator's component count as a compile-time constant (1 or 2).
template <class F>
decltype(auto) by_components(int nc, F&& f) {
  if (nc == 1) return f(std::integral_constant<int, 1>{});
  return f(std::integral_constant<int, 2>{});
}

}  // namespace fretbem::tangential_detail
