// Per-node vectors of the tangential operator's components (1 or 2) as fixed-size Eigen
// vectors: the per-node arithmetic of the tangential passes never allocates. Internal to
// src/contact.
#pragma once

#include <Eigen/Core>
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

/// Calls f with the operator's component count as a compile-time constant (1 or 2).
template <class F>
decltype(auto) by_components(int nc, F&& f) {
  if (nc == 1) return f(std::integral_constant<int, 1>{});
  return f(std::integral_constant<int, 2>{});
}

}  // namespace fretbem::tangential_detail
