// The slip-node step of the tangential solvers: a local Newton step of every slip node with an
// exact line search on the QP, carrying its own force correction under force control.
#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include "workspace.hpp"

namespace fretbem::tangential_detail {

namespace {

// The local Newton moves d = P(tau + omega s) - tau of the slip nodes into w.slip (step, idx,
// val); returns s . d.
template <int NC>
double collect_slip_moves(Workspace& w, const VecField& tau, const VecField& u) {
  const Field& g = *w.inc.bound;
  const NodeSets& sets = w.sets;
  const double omega = 1.0 / w.op.self_compliance();
  const Vec<NC> dU = mean_shift<NC>(sets, w.inc, u, w.op.grid().cell_area());
  VecField& d = w.slip.step;
  w.slip.idx.clear();
  for (auto& v : w.slip.val) v.clear();
  double sd = 0.0;
  for (std::size_t j = 0; j < sets.contact.size(); ++j) {
    if (sets.stick[j]) continue;
    const Eigen::Index k = sets.contact[j];
    const Vec<NC> t = at<NC>(tau, k), s = dU - (at<NC>(u, k) - at<NC>(*w.inc.u0, k));
    Vec<NC> y = t + omega * s;
    const double over = std::max(0.0, y.norm() - g(k));
    if (over > 0.0) y *= g(k) / y.norm();
    // Moves at round-off level (projecting back onto the circle a node that slips outward)
    // are no moves: counting them would make every iteration a dense update.
    const double dd = (y - t).squaredNorm();
    if (!(dd > kTurnRoundoff * kTurnRoundoff * g(k) * g(k))) continue;
    w.slip.idx.push_back(k);
    for (int c = 0; c < NC; ++c) w.slip.val[c].push_back(y(c) - t(c));
    put<NC>(d, k, y - t);
    // s . d without cancellation: with y - t = omega s and t on the circle |t| = g,
    // s . d = (|d|^2 + (|y| - g) |d|^2 / (2 g)) / omega >= 0. The plain dot product loses the
    // O(angle^2) decrease of a small rotation in round-off and stalls near 1e-9 rad.
    sd += dd * (1.0 + over / (2.0 * g(k))) / omega;
  }
  return w.comm().sum(sd);
}

// The image C d of the step on the contact nodes into w.slip.image; with `carry` the stick
// nodes' common share -sum(d) / |S| of the force correction is appended to the step first.
// It adds nothing to s . d: s is mean-free on the stick set under force control (dU is its
// mean).
template <int NC>
void image_step(Workspace& w, bool carry) {
  const NodeSets& sets = w.sets;
  VecField &d = w.slip.step, &dw_image = w.slip.image;
  // Under the analogy the components are decoupled and the stick nodes' uniform shift images
  // as shift x C 1_S (stick_image, kept up to date by sparse updates as in restore_force): the
  // sparse update then covers the slip nodes only. Summing the stick nodes directly made most
  // slip steps a full product (measured: 1451 instead of 1332 convolutions per steady n = 256
  // cycle).
  const bool by_stick_image = carry && w.op.half_space().coupling() == Coupling::analogy;
  // dw_image is read on the contact nodes only (the line search and the u update), so only they
  // are cleared (a whole-grid clear was a pass of the grid per iteration).
  for (auto& f : dw_image)
    for (const Eigen::Index k : sets.contact) f(k) = 0.0;
  if (by_stick_image) w.op.add_sparse_at(w.slip.idx, w.slip.val, d, sets.contact, dw_image);
  if (carry) {
    Vec<NC> sum = Vec<NC>::Zero();
    for (int c = 0; c < NC; ++c)
      for (const double v : w.slip.val[c]) sum(c) += v;
    w.comm().sum(std::span<double>(sum.data(), NC));
    const Vec<NC> shift = -sum / double(sets.nstick);
    for (std::size_t j = 0; j < sets.contact.size(); ++j) {
      if (!sets.stick[j]) continue;
      w.slip.idx.push_back(sets.contact[j]);
      for (int c = 0; c < NC; ++c) w.slip.val[c].push_back(shift(c));
      put<NC>(d, sets.contact[j], shift);
    }
    if (by_stick_image) {
      if (w.comm().any(w.stick_image.stick != sets.stick)) w.update_stick_image();
      for (const Eigen::Index k : sets.contact)
        for (int c = 0; c < NC; ++c) dw_image[c](k) += shift(c) * w.stick_image.image(k);
    }
  }
  if (!by_stick_image) w.op.add_sparse_at(w.slip.idx, w.slip.val, d, sets.contact, dw_image);
}

// tau += theta d on the moved nodes, the first `nslip` of them slip nodes. A damped turn
// (theta < 1) cuts the chord inside the disc; a node whose full step stayed on the bound and
// turned by less than a right angle is put back on it, so turning does not release it. A
// reversal (the full step ends in the opposite half-plane, in 1-D a flip from -g towards +g)
// is not a turn: its damped step re-enters the disc and the node sticks. The put-back changes
// tau, so its change enters u at once (never a traction change u does not see: a stale u made
// CG crawl after the next exact product). Returns whether the stick set changed.
template <int NC>
bool take_step(Workspace& w, double theta, std::size_t nslip, VecField& tau, VecField& u) {
  const Field& g = *w.inc.bound;
  const VecField& d = w.slip.step;
  bool released = false;
  std::vector<Eigen::Index>& back = w.slip.back_idx;
  back.clear();
  for (auto& v : w.slip.back_val) v.clear();
  for (std::size_t i = 0; i < w.slip.idx.size(); ++i) {
    const Eigen::Index k = w.slip.idx[i];
    const Vec<NC> dk = at<NC>(d, k), t0 = at<NC>(tau, k), t = t0 + theta * dk;
    const double m = t.norm();
    if (i >= nslip) {  // a stick node's force correction; over its bound it starts to slip
      const Vec<NC> y = m > g(k) ? Vec<NC>(t * (g(k) / m)) : t;
      if (m > g(k)) {
        released = true;  // the stick set changed
        back.push_back(k);
        for (int c = 0; c < NC; ++c) w.slip.back_val[c].push_back(y(c) - t(c));
      }
      put<NC>(tau, k, y);
      continue;
    }
    const Vec<NC> full = t0 + dk;
    const bool turn = full.norm() >= g(k) * (1.0 - kBoundEps) && full.dot(t0) > 0.0;
    if (turn && m > 0.0 && m < g(k)) {
      const Vec<NC> y = t * (g(k) / m);
      back.push_back(k);
      for (int c = 0; c < NC; ++c) w.slip.back_val[c].push_back(y(c) - t(c));
      put<NC>(tau, k, y);
    } else {
      put<NC>(tau, k, t);
      released |= m < g(k) * (1.0 - kBoundEps);
    }
  }
  w.op.add_sparse(back, w.slip.back_val, tau, u);
  return w.comm().any(released);
}

// Slip nodes move along d = P(tau + omega s) - tau, omega = 1 / C_ii (a local Newton step: it
// turns a node towards its slip and lets a node slipping backwards re-enter its disc), with an
// exact line search on the QP: every point of the segment is feasible and the objective
// decreases, which a plain simultaneous Jacobi step on this dense operator would not ensure.
//
// Under force control the step also carries its own force correction: the stick nodes move by
// the common -sum(d) / |S|, so the direction keeps the total force and the line search sees
// the cost of that correction. Correcting the force afterwards (restore_force) is outside the
// line search, and when few nodes stick it is a feedback with gain above one: the slip ring's
// turn changes the force, the few stick nodes take the difference, their displacement turns
// the slip ring further (measured: rough, Cerruti, force control, 22 of 111 nodes sticking: the
// residual grew 10 % per iteration from 1e-3 to 0.5 with a fixed stick set, then the force
// correction moved every node and the iteration cycled). With the correction inside the direction
// every step decreases the QP objective.
// The largest theta at which every stick node moved by the step (entries nslip.. of
// w.slip.idx, the carried force correction) stays inside its disc: |tau + theta d| = g.
template <int NC>
double feasible_theta(const Workspace& w, std::size_t nslip, const VecField& tau) {
  const Field& g = *w.inc.bound;
  double tmax = std::numeric_limits<double>::infinity();
  for (std::size_t i = nslip; i < w.slip.idx.size(); ++i) {
    const Eigen::Index k = w.slip.idx[i];
    tmax = std::min(tmax, step_to_bound<NC>(at<NC>(tau, k), at<NC>(w.slip.step, k), g(k)));
  }
  return w.comm().min(tmax);
}

template <int NC>
bool slip_node_step_impl(Workspace& w, VecField& tau, VecField& u, bool carry_force,
                         bool feasible) {
  const NodeSets& sets = w.sets;
  VecField &d = w.slip.step, &dw_image = w.slip.image;
  const double sd = collect_slip_moves<NC>(w, tau, u);
  auto clear_step = [&] {
    for (const Eigen::Index k : w.slip.idx) put<NC>(d, k, Vec<NC>::Zero());
  };
  if (!w.comm().any(!w.slip.idx.empty()) || !(sd > 0.0)) {
    clear_step();
    return false;
  }
  const std::size_t nslip = w.slip.idx.size();
  const bool carry = carry_force && w.inc.control == TangentialControl::force && sets.nstick > 0;
  image_step<NC>(w, carry);
  // Exact line search on the QP along d: theta = (s . d) / (d . C d), at most the full step.
  double dw = 0.0;
  for (const Eigen::Index k : w.slip.idx) dw += at<NC>(d, k).dot(at<NC>(dw_image, k));
  dw = w.comm().sum(dw);
  double theta = dw > 0.0 ? std::min(1.0, sd / dw) : 1.0;
  if (feasible && carry) theta = std::min(theta, feasible_theta<NC>(w, nslip, tau));
  for (const Eigen::Index k : sets.contact)
    for (int c = 0; c < NC; ++c) u[c](k) += theta * dw_image[c](k);
  const bool released = take_step<NC>(w, theta, nslip, tau, u);
  clear_step();
  return released;
}

}  // namespace

// The step buffers are made on first use: an increment whose start is already converged
// takes no step and allocates nothing.
bool Workspace::slip_node_step(VecField& tau, VecField& u, bool carry_force, bool feasible) {
  if (slip.step.empty()) slip.step = op.zeros(), slip.image = op.zeros();
  return by_components(op.components(), [&](auto nc) {
    return slip_node_step_impl<decltype(nc)::value>(*this, tau, u, carry_force, feasible);
  });
}

}  // namespace fretbem::tangential_detail
