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

namespace {

// How a change at idx (this rank's nodes) is imaged: not at all, by direct summation, or by a
// full product. The changed nodes of all ranks decide, so that every rank of a distributed
// grid takes the collective product or none does (sparse_limit() is 0 there).
enum class Update { none, sparse, product };

Update update_for(const HalfSpace& hs, std::span<const std::int64_t> idx) {
  const double changed = hs.communicator().sum(double(idx.size()));
  if (changed == 0.0) return Update::none;
  if (changed > double(hs.sparse_limit()) || hs.coupling() != Coupling::analogy)
    return Update::product;
  return Update::sparse;
}

}  // namespace

void TangentialOperator::add_sparse(std::span<const std::int64_t> idx,
                                    const std::vector<std::vector<double>>& val,
                                    const VecField& tau, VecField& u) {
  // Sparse direct summation pays for itself below HalfSpace::sparse_limit() changed nodes.
  const Update how = update_for(hs_, idx);
  if (how == Update::none) return;
  if (how == Update::product) {
    apply(tau, u);
    return;
  }
  for (int c = 0; c < ncomp_; ++c) hs_.tangential_add_sparse(idx, val[c], u[c]);
}

void TangentialOperator::add_sparse_at(std::span<const std::int64_t> idx,
                                       const std::vector<std::vector<double>>& val,
                                       const VecField& tau, std::span<const std::int64_t> targets,
                                       VecField& u) {
  // The same rule as add_sparse, so both take the same branch and give the same bits.
  const Update how = update_for(hs_, idx);
  if (how == Update::none) return;
  if (how == Update::product) {
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

// Each component made zero in place: VecField(n, field) zeroes one field and copies it (a copy
// of the grid per call, several per increment).
VecField TangentialOperator::zeros() const {
  VecField v(static_cast<std::size_t>(ncomp_));
  for (Field& f : v) f = hs_.local_zeros();
  return v;
}

}  // namespace fretbem
