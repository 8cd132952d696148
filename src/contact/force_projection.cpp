// The force projection of the tangential solvers: a common shift of the movable nodes'
// tractions that restores the imposed total force, and its displacement.
#include <Eigen/Dense>
#include <array>
#include <span>
#include <vector>

#include "workspace.hpp"

namespace fretbem::tangential_detail {

// Euclidean projection onto {|tau_i| <= g_i, sum tau h^2 = F} over a set of movable nodes:
// tau_i <- P_i(tau_i + lambda) with one shift lambda, found by safeguarded Newton on the
// monotone map lambda -> sum P_i(tau_i + lambda) (the gradient of a convex function; its
// Jacobian is the sum of the disc projections' Jacobians). Stick nodes move first: shifting
// slip nodes as well would turn them against their slip and, in 2-D, make the iteration cycle.
// Only when the stick nodes cannot carry the force (a reversal under force control) do all
// contact nodes move, which gives a feasible state of the right force.
//
// With no stick node (the whole contact slides) the correction turns the slip nodes along
// their bound instead: sum g_i (tau_i + lambda) / |tau_i + lambda| is the gradient of the
// convex sum g_i |tau_i + lambda|, so the same Newton finds lambda, and every node stays on
// its bound. Projecting instead put a node inside its disc whenever lambda . tau_i <
// -|lambda|^2 / 2, half the contact for a lambda of any size: on the coupled normal ramp
// (beta/mu = 4, n = 32, 4 sub-steps a row) the iterate at residual 2.3e-10 with no stick
// node came back with 104 of 208 stick nodes at 3.1e-2, a cycle of about 95 iterations
// that ended in the stagnation stop.
void Workspace::restore_force(VecField& tau, VecField& u) {
  if (inc.control != TangentialControl::force) return;
  const Field& g = *inc.bound;
  const double tol = 1e-15 * gsum;
  const Eigen::VectorXd want = inc.target / op.grid().cell_area();
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(op.components());
  for (const Eigen::Index k : sets.contact)
    for (int c = 0; c < op.components(); ++c) sum(c) += tau[c](k);
  comm().sum(std::span<double>(sum.data(), sum.size()));
  if ((sum - want).norm() <= tol) return;
  sets.classify(g, tau);
  if (sets.nstick == 0 && shift_to_force(Movable::on_bound, want, tau).mismatch <= tol) {
    op.apply(tau, u);
    return;
  }
  const ForceShift fs = shift_to_force(Movable::stick, want, tau);
  if (fs.mismatch > tol) {
    shift_to_force(Movable::all, want, tau);
    op.apply(tau, u);
    return;
  }
  // Every stick node moved by the same lambda (none reached its bound) and the components are
  // decoupled (analogy): u changes by lambda C 1_S. C 1_S is kept, and when the stick set S
  // changes by few nodes it is updated by direct summation over them, so the correction
  // usually costs no convolution.
  if (!fs.uniform || op.half_space().coupling() != Coupling::analogy) {
    op.apply(tau, u);
    return;
  }
  if (comm().any(stick_image.stick != sets.stick)) update_stick_image();
  // The partition solver returns this u as C tau everywhere (a pass of the grid); the projected
  // solver reads u on the contact nodes only, and its verifying product, when it makes one,
  // sets u everywhere.
  if (!u_on_contact_only) {
    for (std::size_t c = 0; c < u.size(); ++c) u[c] += fs.lambda(c) * stick_image.image;
    return;
  }
  for (std::size_t c = 0; c < u.size(); ++c)
    for (const Eigen::Index k : sets.contact) u[c](k) += fs.lambda(c) * stick_image.image(k);
}

void Workspace::update_stick_image() {
  HalfSpace& hs = op.half_space();
  std::vector<Eigen::Index> changed;
  std::vector<double> sign;
  if (stick_image.stick.size() == sets.stick.size()) {
    for (std::size_t j = 0; j < sets.contact.size(); ++j)
      if (stick_image.stick[j] != sets.stick[j])
        changed.push_back(sets.contact[j]), sign.push_back(sets.stick[j] ? 1.0 : -1.0);
  }
  if (!changed.empty() && changed.size() <= hs.sparse_limit()) {
    hs.tangential_add_sparse(changed, sign, stick_image.image);
  } else {
    Field load = hs.local_zeros();
    for (std::size_t j = 0; j < sets.contact.size(); ++j) load(sets.contact[j]) = sets.stick[j];
    hs.tangential_analogy(load, stick_image.image);
  }
  stick_image.stick = sets.stick;
}

namespace {

template <int NC>
ForceShift shift_to_force_impl(const NodeSets& sets, const Field& g, double gsum, Movable movable,
                               const Eigen::VectorXd& want_, VecField& tau) {
  const bool all = movable != Movable::stick, on_bound = movable == Movable::on_bound;
  const Vec<NC> want = want_;
  // The movable nodes' starting traction; the others contribute a constant to the total.
  std::vector<Eigen::Index> nodes;
  std::vector<Vec<NC>, Eigen::aligned_allocator<Vec<NC>>> base;
  Vec<NC> fixed = Vec<NC>::Zero();
  for (std::size_t j = 0; j < sets.contact.size(); ++j) {
    const Eigen::Index k = sets.contact[j];
    if (all || sets.stick[j])
      nodes.push_back(k), base.push_back(at<NC>(tau, k));
    else
      fixed += at<NC>(tau, k);
  }
  bool clamped = false;
  const bool none = sets.comm->sum(double(nodes.size())) == 0.0;
  // One message per trial shift: the total, the Jacobian and "clamped" over the ranks.
  std::array<double, NC + NC * NC + 1> sums;
  auto apply = [&](const Vec<NC>& l, Vec<NC>& sum, Mat<NC>& J) {
    sum = fixed;
    J.setZero();
    clamped = false;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      const Eigen::Index k = nodes[i];
      Vec<NC> y = base[i] + l;
      const double m = y.norm();
      if (m <= g(k) && !on_bound) {
        J += Mat<NC>::Identity();
      } else if (m > 0.0) {
        J += (g(k) / m) * (Mat<NC>::Identity() - y * y.transpose() / (m * m));
        y *= g(k) / m;
        clamped = true;
      }
      put<NC>(tau, k, y);
      sum += y;
    }
    Eigen::Map<Vec<NC>>(sums.data()) = sum;
    Eigen::Map<Mat<NC>>(sums.data() + NC) = J;
    sums[NC + NC * NC] = clamped ? 1.0 : 0.0;
    sets.comm->sum(sums);
    sum = Eigen::Map<Vec<NC>>(sums.data()), J = Eigen::Map<Mat<NC>>(sums.data() + NC);
    clamped = sums[NC + NC * NC] > 0.0;
  };
  // Typically one Newton step: while no stick node reaches its bound the map is linear.
  const NewtonPoint<NC> p = monotone_newton<NC>(apply, Vec<NC>::Zero(), want, 1e-15 * gsum, 200);
  Vec<NC> sum;
  Mat<NC> J;
  if (!p.evaluated_at_x) apply(p.x, sum, J);  // tau holds P(base + lambda) again
  const double err = p.mismatch;
  const Vec<NC> lambda = p.x;
  ForceShift r;
  r.mismatch = err;
  r.lambda = lambda;
  r.uniform = !clamped && !none;
  return r;
}

}  // namespace

ForceShift Workspace::shift_to_force(Movable movable, const Eigen::VectorXd& want,
                                     VecField& tau) const {
  return by_components(int(tau.size()), [&](auto nc) {
    return shift_to_force_impl<decltype(nc)::value>(sets, *inc.bound, gsum, movable, want, tau);
  });
}

}  // namespace fretbem::tangential_detail
