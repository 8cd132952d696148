#include "fretbem/contact/tangential_operator.hpp"

namespace fretbem {

TangentialOperator::TangentialOperator(HalfSpace& hs) : hs_(hs), ncomp_(2) {}

TangentialOperator::TangentialOperator(HalfSpace& hs, Vec2 direction)
    : hs_(hs), ncomp_(1), e_(direction.normalized()) {}

void TangentialOperator::apply(const VecField& tau, VecField& u) {
  u.resize(ncomp_);
  if (ncomp_ == 1)
    hs_.tangential_analogy(tau[0], u[0]);
  else
    hs_.tangential(tau[0], tau[1], u[0], u[1]);
}

void TangentialOperator::add_sparse(std::span<const std::int64_t> idx,
                                    const std::vector<std::vector<double>>& val,
                                    const VecField& tau, VecField& u) {
  if (idx.empty()) return;
  // Sparse direct summation pays for itself below HalfSpace::sparse_limit() changed nodes.
  if (idx.size() > hs_.sparse_limit() || hs_.coupling() != Coupling::analogy) {
    apply(tau, u);
    return;
  }
  for (int c = 0; c < ncomp_; ++c) hs_.tangential_add_sparse(idx, val[c], u[c]);
}

void TangentialOperator::add_sparse_at(std::span<const std::int64_t> idx,
                                       const std::vector<std::vector<double>>& val,
                                       const VecField& tau, std::span<const std::int64_t> targets,
                                       VecField& u) {
  if (idx.empty()) return;
  // The same rule as add_sparse, so both take the same branch and give the same bits.
  if (idx.size() > hs_.sparse_limit() || hs_.coupling() != Coupling::analogy) {
    apply(tau, u);
    return;
  }
  for (int c = 0; c < ncomp_; ++c) hs_.tangential_add_sparse_at(idx, val[c], targets, u[c]);
}

double TangentialOperator::self_compliance() const {
  return hs_.normal_self() * hs_.tangential_ratio();
}

Eigen::VectorXd TangentialOperator::to_local(Vec2 v) const {
  if (ncomp_ == 1) return Eigen::VectorXd::Constant(1, e_.dot(v));
  return v;
}

Vec2 TangentialOperator::to_global(const Eigen::VectorXd& v) const {
  if (ncomp_ == 1) return v(0) * e_;
  return Vec2(v(0), v(1));
}

VecField TangentialOperator::zeros() const {
  return VecField(ncomp_, hs_.grid().zeros());
}

}  // namespace fretbem
