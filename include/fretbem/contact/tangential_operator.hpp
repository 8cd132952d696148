// TangentialOperator: the tangential compliance C (m/Pa) restricted to the traction
// components a scene actually loads. One component along a fixed direction e when the coupling
// is the Cattaneo–Mindlin analogy and the whole history is collinear (then tau = tau_e e and
// tau_perp stays exactly zero: no y-solve); two components (x, y) otherwise.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

#include "fretbem/elastic/half_space.hpp"

namespace fretbem {

/// A field of traction or displacement vectors: comps[0] (and comps[1] in 2-D).
using VecField = std::vector<Field>;
using Vec2 = Eigen::Vector2d;

class TangentialOperator {
 public:
  /// Two-component operator with the half-space's coupling.
  explicit TangentialOperator(HalfSpace& hs);
  /// One-component operator along the unit direction e (analogy only).
  TangentialOperator(HalfSpace& hs, Vec2 direction);

  int components() const { return ncomp_; }
  /// Unit direction of the single component (1-D mode).
  Vec2 direction() const { return e_; }
  const Grid& grid() const { return hs_.grid(); }
  HalfSpace& half_space() { return hs_; }

  /// u = C tau.
  void apply(const VecField& tau, VecField& u);
  /// u += C e for a sparse change e (per component values at the given nodes); falls back to
  /// a full product u = C tau when sparse updates are not available or not cheaper.
  void add_sparse(std::span<const std::int64_t> idx, const std::vector<std::vector<double>>& val,
                  const VecField& tau, VecField& u);
  /// The same, but the sparse update reaches only the `targets` nodes (sorted grid indices;
  /// elsewhere u keeps its old values): for images read only on the contact nodes. Bit for
  /// bit add_sparse's values on the targets; the fallback product still sets all of u.
  void add_sparse_at(std::span<const std::int64_t> idx, const std::vector<std::vector<double>>& val,
                     const VecField& tau, std::span<const std::int64_t> targets, VecField& u);
  /// Diagonal compliance of one node (m/Pa): for Jacobi-type local updates.
  double self_compliance() const;

  /// Components of a global vector (x, y) in this operator's basis, and back.
  Eigen::VectorXd to_local(Vec2 v) const;
  Vec2 to_global(const Eigen::VectorXd& v) const;
  /// Zero VecField of the right shape.
  VecField zeros() const;

 private:
  HalfSpace& hs_;
  int ncomp_;
  Vec2 e_{1.0, 0.0};
};

}  // namespace fretbem
