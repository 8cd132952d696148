#include "node_sets.hpp"

#include <array>
#include <cmath>

namespace fretbem::tangential_detail {

Field magnitude(const VecField& tau) {
  Field m = tau[0].square();
  for (std::size_t c = 1; c < tau.size(); ++c) m += tau[c].square();
  return m.sqrt();
}

Field free_mask(const Field& g, const Field& mag) {
  return ((g > 0.0) && (mag < g * (1.0 - kBoundEps))).cast<double>();
}

Eigen::VectorXd total_force(const VecField& tau, const Grid& grid, const Communicator& comm) {
  Eigen::VectorXd F(tau.size());
  for (std::size_t c = 0; c < tau.size(); ++c) F(c) = tau[c].sum();
  comm.sum(std::span<double>(F.data(), F.size()));
  return F * grid.cell_area();
}

double bound_force(const Field& g, const Grid& grid, const Communicator& comm) {
  return comm.sum(g.sum()) * grid.cell_area();
}

Eigen::VectorXd shift_estimate(const TangentialIncrement& inc, const VecField& u, const Field& free,
                               const Communicator& comm) {
  if (inc.control == TangentialControl::displacement) return inc.target;
  // Force control: the rigid shift is the common displacement increment of the stick nodes.
  const Field& w = comm.sum(free.sum()) > 0 ? free : Field((*inc.bound > 0.0).cast<double>());
  const double n = std::max(1.0, comm.sum(w.sum()));
  Eigen::VectorXd dU(u.size());
  for (std::size_t c = 0; c < u.size(); ++c) dU(c) = (w * (u[c] - (*inc.u0)[c])).sum();
  comm.sum(std::span<double>(dU.data(), dU.size()));
  return dU / n;
}

// Exactly mu F_z is full sliding too: the force residual is relative to
// sum g h^2, so a target within the tolerance of it cannot be told apart from it, and the QP's
// stick set would have to vanish exactly (measured: 5000 iterations, residual 0.15).
bool past_full_sliding(const TangentialIncrement& inc, const Grid& grid, double tolerance,
                       const Communicator& comm) {
  if (inc.control != TangentialControl::force) return false;
  return past_full_sliding(inc, bound_force(*inc.bound, grid, comm), tolerance);
}

bool past_full_sliding(const TangentialIncrement& inc, double bound_force, double tolerance) {
  return inc.control == TangentialControl::force &&
         !(inc.target.norm() < bound_force * (1.0 - tolerance));
}

// Squared magnitudes compared, the root taken only on nodes that move: a magnitude field of
// the whole grid (a temporary and a root per cell) cost 8 % of a steady n = 256 cycle (perf).
bool project_all(const Field& g, VecField& tau, const Communicator& comm) {
  bool moved = false;
  for (Eigen::Index k = 0; k < g.size(); ++k) {
    double m2 = 0.0;
    for (const auto& t : tau) m2 += t(k) * t(k);
    if (m2 == 0.0 || m2 < g(k) * g(k)) continue;  // |t| < g: rounding is monotone
    const double m = std::sqrt(m2);
    if (m <= g(k)) continue;
    const double f = g(k) > 0.0 ? g(k) / m : 0.0;
    for (auto& t : tau) t(k) *= f;
    moved = true;
  }
  return comm.any(moved);
}

namespace {

template <int NC>
std::int64_t classify_impl(NodeSets& sets, const Field& g, const VecField& tau) {
  sets.nstick = 0;
  for (std::size_t j = 0; j < sets.contact.size(); ++j) {
    const Eigen::Index k = sets.contact[j];
    const bool s = at<NC>(tau, k).norm() < g(k) * (1.0 - kBoundEps);
    sets.stick[j] = s;
  }
  sets.count_stick();
  return sets.nstick;
}

// classify and mean_shift in one pass over the contact nodes (the residual's first two passes
// were a fifth of its time): the same flags, and the stick nodes' sum of u - u0 in the same
// order. With no stick node the shift over all contact nodes takes its own passes (mean_shift).
template <int NC>
Vec<NC> classify_and_shift(NodeSets& sets, const TangentialIncrement& inc, const VecField& tau,
                           const VecField& u, double cell_area) {
  const Field& g = *inc.bound;
  const VecField& u0 = *inc.u0;
  const bool force = inc.control == TangentialControl::force;
  std::int64_t local = 0;
  Vec<NC> sum = Vec<NC>::Zero();
  for (std::size_t j = 0; j < sets.contact.size(); ++j) {
    const Eigen::Index k = sets.contact[j];
    const bool s = at<NC>(tau, k).norm() < g(k) * (1.0 - kBoundEps);
    sets.stick[j] = s;
    local += s;
    if (force && s) sum += at<NC>(u, k) - at<NC>(u0, k);
  }
  // One message for the count and the sum (the count first, as count_stick sends it).
  std::array<double, 1 + NC> totals;
  totals[0] = double(local);
  Eigen::Map<Vec<NC>>(totals.data() + 1) = sum;
  sets.comm->sum(totals);
  sets.nstick = std::int64_t(totals[0]);
  if (!force) return inc.target;
  if (sets.nstick == 0) return mean_shift<NC>(sets, inc, u, cell_area);
  return Eigen::Map<Vec<NC>>(totals.data() + 1) / double(sets.nstick);
}

// One pass: stick nodes must not slip; slip nodes may slip only outward along their traction
// (beyond the round-off of the slip, kSlipRoundoff). The CG gradient norm stick_slip2 is the
// whole stick slip.
template <int NC>
double residual_impl(NodeSets& sets, const TangentialIncrement& inc, const VecField& tau,
                     const VecField& u, double scale, const Grid& grid, Eigen::VectorXd& dU,
                     double& stick_slip2) {
  const Field& g = *inc.bound;
  const Vec<NC> shift = classify_and_shift<NC>(sets, inc, tau, u, grid.cell_area());
  double stick2 = 0.0, net2 = 0.0, gsum = 0.0;
  Vec<NC> force = Vec<NC>::Zero();
  for (std::size_t j = 0; j < sets.contact.size(); ++j) {
    const Eigen::Index k = sets.contact[j];
    const Vec<NC> t = at<NC>(tau, k), s = shift - (at<NC>(u, k) - at<NC>(*inc.u0, k));
    force += t, gsum += g(k);
    const double floor =
        kSlipRoundoff * (shift.norm() + at<NC>(u, k).norm() + at<NC>(*inc.u0, k).norm());
    if (sets.stick[j]) {
      stick2 += s.squaredNorm();
      net2 += std::max(0.0, s.squaredNorm() - floor * floor);
      continue;
    }
    const double m = t.norm();
    Vec<NC> across = s;
    if (m > 0.0) {
      const Vec<NC> unit = t / m;
      across -= std::max(0.0, s.dot(unit)) * unit;
    }
    net2 += std::max(0.0, across.squaredNorm() - floor * floor);
  }
  // One message for the pass's sums (summed in locals: the loop keeps them in registers).
  std::array<double, 3 + NC> sums{stick2, net2, gsum};
  Eigen::Map<Vec<NC>>(sums.data() + 3) = force;
  sets.comm->sum(sums);
  stick2 = sums[0], net2 = sums[1], gsum = sums[2];
  force = Eigen::Map<Vec<NC>>(sums.data() + 3);
  dU = shift;
  stick_slip2 = stick2;
  double res = std::sqrt(net2 / std::max(1.0, double(sets.ncontact))) / scale;
  if (inc.control == TangentialControl::force) {
    // Force mismatch relative to the full-sliding force sum g h^2.
    const double area = grid.cell_area();
    res = std::max(res, (force * area - inc.target).norm() / (gsum * area));
  }
  return res;
}

}  // namespace

NodeSets::NodeSets(const Field& g, const Communicator& comm_) : comm(&comm_) {
  for (Eigen::Index k = 0; k < g.size(); ++k)
    if (g(k) > 0.0) contact.push_back(k);
  stick.assign(contact.size(), 0);
  ncontact = std::int64_t(comm->sum(double(contact.size())));
}

void NodeSets::count_stick() {
  std::int64_t local = 0;
  for (const std::uint8_t s : stick) local += s;
  nstick = std::int64_t(comm->sum(double(local)));
}

std::int64_t NodeSets::classify(const Field& g, const VecField& tau) {
  return by_components(int(tau.size()),
                       [&](auto nc) { return classify_impl<decltype(nc)::value>(*this, g, tau); });
}

double residual(NodeSets& sets, const TangentialIncrement& inc, const VecField& tau,
                const VecField& u, double scale, const Grid& grid, Eigen::VectorXd& dU,
                double& stick_slip2) {
  return by_components(int(tau.size()), [&](auto nc) {
    return residual_impl<decltype(nc)::value>(sets, inc, tau, u, scale, grid, dU, stick_slip2);
  });
}

NodeSets::NodeSets(const BoundCache& bound, const Communicator& comm_)
    : comm(&comm_),
      contact(bound.contact()),
      stick(contact.size(), 0),
      ncontact(bound.ncontact()) {}

const BoundCache& BoundCache::update(TangentialOperator& op, const Field& g) {
  const Communicator& comm = op.half_space().communicator();
  // The cached bound must match on every rank: the product below is collective.
  if (comm.min(same_bits(g_, g) ? 1.0 : 0.0) > 0.0) return *this;
  g_ = g;
  contact_.clear();
  for (Eigen::Index k = 0; k < g.size(); ++k)
    if (g(k) > 0.0) contact_.push_back(k);
  ncontact_ = std::int64_t(comm.sum(double(contact_.size())));
  gsum_ = comm.sum(g.sum());
  VecField load = op.zeros(), u;
  load[0] = g;
  op.apply(load, u);
  const Field on_contact = (g > 0.0).cast<double>();
  const double n = comm.sum(on_contact.sum());
  scale_ = n > 0 ? std::sqrt(comm.sum((on_contact * u[0].square()).sum()) / n) : 1.0;
  if (!(scale_ > 0.0)) scale_ = 1.0;
  return *this;
}

}  // namespace fretbem::tangential_detail
