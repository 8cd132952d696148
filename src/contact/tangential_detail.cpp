#include "tangential_detail.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <sstream>
#include <type_traits>

#include "fretbem/core/errors.hpp"

namespace fretbem::tangential_detail {

Field magnitude(const VecField& tau) {
  Field m = tau[0].square();
  for (std::size_t c = 1; c < tau.size(); ++c) m += tau[c].square();
  return m.sqrt();
}

Field free_mask(const Field& g, const Field& mag) {
  return ((g > 0.0) && (mag < g * (1.0 - kBoundEps))).cast<double>();
}

Eigen::VectorXd total_force(const VecField& tau, const Grid& grid) {
  Eigen::VectorXd F(tau.size());
  for (std::size_t c = 0; c < tau.size(); ++c) F(c) = tau[c].sum() * grid.cell_area();
  return F;
}

double bound_force(const Field& g, const Grid& grid) {
  return g.sum() * grid.cell_area();
}

Eigen::VectorXd shift_estimate(const TangentialIncrement& inc, const VecField& u,
                               const Field& free) {
  if (inc.control == TangentialControl::displacement) return inc.target;
  // Force control: the rigid shift is the common displacement increment of the stick nodes.
  const Field& w = free.sum() > 0 ? free : Field((*inc.bound > 0.0).cast<double>());
  const double n = std::max(1.0, w.sum());
  Eigen::VectorXd dU(u.size());
  for (std::size_t c = 0; c < u.size(); ++c) dU(c) = (w * (u[c] - (*inc.u0)[c])).sum() / n;
  return dU;
}

// Exactly mu F_z (issue 14, item 6) is full sliding too: the force residual is relative to
// sum g h^2, so a target within the tolerance of it cannot be told apart from it, and the QP's
// stick set would have to vanish exactly (measured: 5000 iterations, residual 0.15).
bool past_full_sliding(const TangentialIncrement& inc, const Grid& grid, double tolerance) {
  if (inc.control != TangentialControl::force) return false;
  return !(inc.target.norm() < bound_force(*inc.bound, grid) * (1.0 - tolerance));
}

bool project_all(const Field& g, VecField& tau) {
  const Field mag = magnitude(tau);
  bool moved = false;
  for (Eigen::Index k = 0; k < g.size(); ++k) {
    if (mag(k) <= g(k)) continue;
    const double f = g(k) > 0.0 ? g(k) / mag(k) : 0.0;
    for (auto& t : tau) t(k) *= f;
    moved = true;
  }
  return moved;
}

namespace {

// Per-node vectors of the operator's components: fixed size, so the per-node arithmetic of the
// passes below never allocates (the dynamic VectorXd/MatrixXd of the earlier version did, in
// the per-node Newton of the force projection).
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

/// dU: imposed (displacement control), or the mean of u - u0 over the stick nodes (over all
/// contact nodes when none sticks) under force control.
template <int NC>
Vec<NC> mean_shift(const NodeSets& sets, const TangentialIncrement& inc, const VecField& u) {
  if (inc.control == TangentialControl::displacement) return inc.target;
  const bool all = sets.nstick == 0;
  Vec<NC> sum = Vec<NC>::Zero();
  for (std::size_t j = 0; j < sets.contact.size(); ++j) {
    if (!all && !sets.stick[j]) continue;
    const Eigen::Index k = sets.contact[j];
    sum += at<NC>(u, k) - at<NC>(*inc.u0, k);
  }
  return sum / std::max(1.0, double(all ? sets.contact.size() : sets.nstick));
}

template <int NC>
std::int64_t classify_impl(NodeSets& sets, const Field& g, const VecField& tau) {
  sets.nstick = 0;
  for (std::size_t j = 0; j < sets.contact.size(); ++j) {
    const Eigen::Index k = sets.contact[j];
    const bool s = at<NC>(tau, k).norm() < g(k) * (1.0 - kBoundEps);
    sets.stick[j] = s;
    sets.nstick += s;
  }
  return sets.nstick;
}

// One pass: stick nodes must not slip; slip nodes may slip only outward along their traction.
template <int NC>
double residual_impl(NodeSets& sets, const TangentialIncrement& inc, const VecField& tau,
                     const VecField& u, double scale, const Grid& grid, Eigen::VectorXd& dU,
                     double& stick_slip2) {
  const Field& g = *inc.bound;
  classify_impl<NC>(sets, g, tau);
  const Vec<NC> shift = mean_shift<NC>(sets, inc, u);
  double stick2 = 0.0, slip2 = 0.0, gsum = 0.0;
  Vec<NC> force = Vec<NC>::Zero();
  for (std::size_t j = 0; j < sets.contact.size(); ++j) {
    const Eigen::Index k = sets.contact[j];
    const Vec<NC> t = at<NC>(tau, k), s = shift - (at<NC>(u, k) - at<NC>(*inc.u0, k));
    force += t, gsum += g(k);
    if (sets.stick[j]) {
      stick2 += s.squaredNorm();
      continue;
    }
    const double m = t.norm();
    if (m > 0.0) {
      const Vec<NC> unit = t / m;
      slip2 += (s - std::max(0.0, s.dot(unit)) * unit).squaredNorm();
    } else {
      slip2 += s.squaredNorm();
    }
  }
  dU = shift;
  stick_slip2 = stick2;
  double res = std::sqrt((stick2 + slip2) / std::max(1.0, double(sets.contact.size()))) / scale;
  if (inc.control == TangentialControl::force) {
    // Force mismatch relative to the full-sliding force sum g h^2.
    const double area = grid.cell_area();
    res = std::max(res, (force * area - inc.target).norm() / (gsum * area));
  }
  return res;
}

}  // namespace

NodeSets::NodeSets(const Field& g) {
  for (Eigen::Index k = 0; k < g.size(); ++k)
    if (g(k) > 0.0) contact.push_back(k);
  stick.assign(contact.size(), 0);
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

double ScaleCache::get(TangentialOperator& op, const Field& g) {
  if (g_.size() == g.size() && (g_ == g).all()) return scale_;
  g_ = g;
  VecField load = op.zeros(), u;
  load[0] = g;
  op.apply(load, u);
  const Field contact = (g > 0.0).cast<double>();
  const double n = contact.sum();
  scale_ = n > 0 ? std::sqrt((contact * u[0].square()).sum() / n) : 1.0;
  if (!(scale_ > 0.0)) scale_ = 1.0;
  return scale_;
}

Workspace::Workspace(TangentialOperator& op_, const TangentialIncrement& inc_,
                     TangentialOptions opt_, ScaleCache& cache)
    : op(op_), inc(inc_), opt(opt_), sets(*inc_.bound) {
  conv0 = op.half_space().convolutions();
  scale = cache.get(op, *inc.bound);
  if (past_full_sliding(inc, op.grid(), opt.tolerance)) {
    const double fmax = bound_force(*inc.bound, op.grid());
    {
      std::ostringstream msg;
      msg << "tangential force " << inc.target.norm() << " N is not below the full-sliding force "
          << "mu F_z = " << fmax << " N: force control cannot go past full sliding";
      throw SolverError(msg.str());
    }
  }
  gsum = inc.bound->sum();
  slip_step = op.zeros(), slip_image = op.zeros();
  val.resize(op.components());
  back_val.resize(op.components());
}

void Workspace::start(VecField& tau, VecField& u) {
  const bool moved = project_all(*inc.bound, tau);
  if (moved || u.size() != tau.size()) op.apply(tau, u), exact = true;
  if (inc.control == TangentialControl::force) start_force(tau, u);
  if (inc.guess) start_guess(tau, u);
}

double Workspace::energy(const VecField& t, const VecField& w) const {
  double e = 0.0;
  for (std::size_t c = 0; c < t.size(); ++c) {
    const Field dt = t[c] - (*inc.tau0)[c];
    e += 0.5 * (dt * (w[c] - (*inc.u0)[c])).sum();
    // Under force control sum dtau is fixed, so the shift term is the same for every start.
    if (inc.control == TangentialControl::displacement) e -= inc.target(c) * dt.sum();
  }
  return e;
}

// The predictor made feasible (inside the discs; under force control shifted to the target
// force as start_force does), imaged by one product, and kept when its QP energy is below the
// current start's. A predictor close to the solution (the same step of the previous cycle of
// a periodic history) then leaves the solver little or nothing to do.
void Workspace::start_guess(VecField& tau, VecField& u) {
  const Field& g = *inc.bound;
  VecField tg = *inc.guess;
  if (tg.size() != tau.size()) return;
  project_all(g, tg);
  if (inc.control == TangentialControl::force) {
    const double tol = 1e-15 * gsum;
    const Eigen::VectorXd want = inc.target / op.grid().cell_area();
    sets.classify(g, tg);
    if (shift_to_force(false, want, tg).mismatch > tol &&
        shift_to_force(true, want, tg).mismatch > tol)
      return;
  }
  VecField ug;
  op.apply(tg, ug);
  if (!(energy(tg, ug) < energy(tau, u))) return;
  tau = std::move(tg), u = std::move(ug);
  exact = true;
}

double Workspace::residual(const VecField& tau, const VecField& u, double& stick_slip2) {
  return tangential_detail::residual(sets, inc, tau, u, scale, op.grid(), result.shift,
                                     stick_slip2);
}

// Force control: of the two feasible starts of the right force — shifting the stick nodes
// only (continued loading) or every contact node (a reversal, where the whole contact sticks
// again first) — take the one of lower QP energy 1/2 (tau - tau0) . (u - u0).
void Workspace::start_force(VecField& tau, VecField& u) {
  const Field& g = *inc.bound;
  const double area = op.grid().cell_area(), tol = 1e-15 * g.sum();
  const Eigen::VectorXd want = inc.target / area;
  if ((total_force(tau, op.grid()) / area - want).norm() <= tol) return;
  VecField ta = tau, ua, tb = tau, ub;
  sets.classify(g, tau);
  const bool a_ok = shift_to_force(false, want, ta).mismatch <= tol;
  shift_to_force(true, want, tb);
  op.apply(tb, ub);
  if (a_ok) {
    op.apply(ta, ua);
    if (energy(ta, ua) < energy(tb, ub)) {
      tau = std::move(ta), u = std::move(ua), exact = true;
      return;
    }
  }
  tau = std::move(tb), u = std::move(ub), exact = true;
}

// Euclidean projection onto {|tau_i| <= g_i, sum tau h^2 = F} over a set of movable nodes:
// tau_i <- P_i(tau_i + lambda) with one shift lambda, found by safeguarded Newton on the
// monotone map lambda -> sum P_i(tau_i + lambda) (the gradient of a convex function; its
// Jacobian is the sum of the disc projections' Jacobians). Stick nodes move first: shifting
// slip nodes as well would turn them against their slip and, in 2-D, make the iteration cycle.
// Only when the stick nodes cannot carry the force (a reversal under force control) do all
// contact nodes move, which gives a feasible state of the right force.
void Workspace::restore_force(VecField& tau, VecField& u) {
  if (inc.control != TangentialControl::force) return;
  const Field& g = *inc.bound;
  const double tol = 1e-15 * gsum;
  const Eigen::VectorXd want = inc.target / op.grid().cell_area();
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(op.components());
  for (const Eigen::Index k : sets.contact)
    for (int c = 0; c < op.components(); ++c) sum(c) += tau[c](k);
  if ((sum - want).norm() <= tol) return;
  sets.classify(g, tau);
  const ForceShift fs = shift_to_force(false, want, tau);
  if (fs.mismatch > tol) {
    shift_to_force(true, want, tau);
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
  if (image_stick != sets.stick) update_stick_image();
  // Full field (one cheap pass): the partition solver returns this u as C tau everywhere.
  for (std::size_t c = 0; c < u.size(); ++c) u[c] += fs.lambda(c) * stick_image;
}

void Workspace::update_stick_image() {
  HalfSpace& hs = op.half_space();
  std::vector<Eigen::Index> changed;
  std::vector<double> sign;
  if (image_stick.size() == sets.stick.size()) {
    for (std::size_t j = 0; j < sets.contact.size(); ++j)
      if (image_stick[j] != sets.stick[j])
        changed.push_back(sets.contact[j]), sign.push_back(sets.stick[j] ? 1.0 : -1.0);
  }
  if (!changed.empty() && changed.size() <= hs.sparse_limit()) {
    hs.tangential_add_sparse(changed, sign, stick_image);
  } else {
    Field load = op.grid().zeros();
    for (std::size_t j = 0; j < sets.contact.size(); ++j) load(sets.contact[j]) = sets.stick[j];
    hs.tangential_analogy(load, stick_image);
  }
  image_stick = sets.stick;
}

namespace {

template <int NC>
ForceShift shift_to_force_impl(const NodeSets& sets, const Field& g, double gsum, bool all,
                               const Eigen::VectorXd& want_, VecField& tau) {
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
  auto apply = [&](const Vec<NC>& l, Vec<NC>& sum, Mat<NC>& J) {
    sum = fixed;
    J.setZero();
    clamped = false;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      const Eigen::Index k = nodes[i];
      Vec<NC> y = base[i] + l;
      const double m = y.norm();
      if (m <= g(k)) {
        J += Mat<NC>::Identity();
      } else {
        J += (g(k) / m) * (Mat<NC>::Identity() - y * y.transpose() / (m * m));
        y *= g(k) / m;
        clamped = true;
      }
      put<NC>(tau, k, y);
      sum += y;
    }
  };
  Vec<NC> lambda = Vec<NC>::Zero(), sum, trial;
  Mat<NC> J, trial_J;
  apply(lambda, sum, J);
  double err = (sum - want).norm();
  bool at_lambda = true;  // tau holds P(base + lambda)
  // Typically one Newton step: while no stick node reaches its bound the map is linear.
  for (int it = 0; it < 200 && err > 1e-15 * gsum; ++it) {
    // Newton step (regularised where the map is flat), halved until the mismatch shrinks.
    J += (1e-12 * J.trace() + 1e-300) * Mat<NC>::Identity();
    Vec<NC> step = J.ldlt().solve(want - sum);
    int half = 0;
    for (; half < 60; ++half, step *= 0.5) {
      apply(lambda + step, trial, trial_J);
      if ((trial - want).norm() < err) break;
    }
    if (half == 60) {  // no shift of these nodes reduces the mismatch
      at_lambda = false;
      break;
    }
    lambda += step, sum = trial, J = trial_J;
    err = (sum - want).norm();
  }
  if (!at_lambda) apply(lambda, sum, J);
  ForceShift r;
  r.mismatch = err;
  r.lambda = lambda;
  r.uniform = !clamped && !nodes.empty();
  return r;
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
// the slip ring further (measured, issue 18 case 77: rough, Cerruti, force control, 22 of 111
// nodes sticking: the residual grew 10 % per iteration from 1e-3 to 0.5 with a fixed stick
// set, then the force correction moved every node and the iteration cycled). With the
// correction inside the direction every step decreases the QP objective.
template <int NC>
bool slip_node_step_impl(Workspace& w, VecField& tau, VecField& u, bool carry_force) {
  const Field& g = *w.inc.bound;
  const NodeSets& sets = w.sets;
  const double omega = 1.0 / w.op.self_compliance();
  const Vec<NC> dU = mean_shift<NC>(sets, w.inc, u);
  VecField &d = w.slip_step, &dw_image = w.slip_image;
  w.idx.clear();
  for (auto& v : w.val) v.clear();
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
    if (!(dd > 1e-28 * g(k) * g(k))) continue;
    w.idx.push_back(k);
    for (int c = 0; c < NC; ++c) w.val[c].push_back(y(c) - t(c));
    put<NC>(d, k, y - t);
    // s . d without cancellation: with y - t = omega s and t on the circle |t| = g,
    // s . d = (|d|^2 + (|y| - g) |d|^2 / (2 g)) / omega >= 0. The plain dot product loses the
    // O(angle^2) decrease of a small rotation in round-off and stalls near 1e-9 rad.
    sd += dd * (1.0 + over / (2.0 * g(k))) / omega;
  }
  auto clear_step = [&] {
    for (const Eigen::Index k : w.idx) put<NC>(d, k, Vec<NC>::Zero());
  };
  if (w.idx.empty() || !(sd > 0.0)) {
    clear_step();
    return false;
  }
  // The stick nodes' share of the force correction. It adds nothing to s . d: s is mean-free
  // on the stick set under force control (dU is its mean).
  const std::size_t nslip = w.idx.size();
  const bool carry = carry_force && w.inc.control == TangentialControl::force && sets.nstick > 0;
  // Under the analogy the components are decoupled and the stick nodes' uniform shift images
  // as shift x C 1_S (stick_image, kept up to date by sparse updates as in restore_force): the
  // sparse update then covers the slip nodes only. Summing the stick nodes directly made most
  // slip steps a full product (issue 13: 1332 -> 1451 convolutions per steady n = 256 cycle).
  const bool by_stick_image = carry && w.op.half_space().coupling() == Coupling::analogy;
  for (auto& f : dw_image) f.setZero();
  // dw_image is read on the contact nodes only (the line search and the u update below).
  if (by_stick_image) w.op.add_sparse_at(w.idx, w.val, d, sets.contact, dw_image);
  if (carry) {
    Vec<NC> shift;
    for (int c = 0; c < NC; ++c) {
      double sum = 0.0;
      for (const double v : w.val[c]) sum += v;
      shift(c) = -sum / double(sets.nstick);
    }
    for (std::size_t j = 0; j < sets.contact.size(); ++j) {
      if (!sets.stick[j]) continue;
      w.idx.push_back(sets.contact[j]);
      for (int c = 0; c < NC; ++c) w.val[c].push_back(shift(c));
      put<NC>(d, sets.contact[j], shift);
    }
    if (by_stick_image) {
      if (w.image_stick != sets.stick) w.update_stick_image();
      for (const Eigen::Index k : sets.contact)
        for (int c = 0; c < NC; ++c) dw_image[c](k) += shift(c) * w.stick_image(k);
    }
  }
  if (!by_stick_image) w.op.add_sparse_at(w.idx, w.val, d, sets.contact, dw_image);
  double dw = 0.0;
  for (const Eigen::Index k : w.idx) dw += at<NC>(d, k).dot(at<NC>(dw_image, k));
  const double theta = dw > 0.0 ? std::min(1.0, sd / dw) : 1.0;
  for (const Eigen::Index k : sets.contact)
    for (int c = 0; c < NC; ++c) u[c](k) += theta * dw_image[c](k);
  // A damped turn (theta < 1) cuts the chord inside the disc; a node whose full step stayed
  // on the bound and turned by less than a right angle is put back on it, so turning does not
  // release it. A reversal (the full step ends in the opposite half-plane, in 1-D a flip from
  // -g towards +g) is not a turn: its damped step re-enters the disc and the node sticks.
  // The put-back changes tau, so its change enters u at once (never a traction change u does
  // not see: a stale u made CG crawl after the next exact product, issue 12).
  bool released = false;
  std::vector<Eigen::Index>& back = w.back_idx;
  back.clear();
  for (auto& v : w.back_val) v.clear();
  for (std::size_t i = 0; i < w.idx.size(); ++i) {
    const Eigen::Index k = w.idx[i];
    const Vec<NC> dk = at<NC>(d, k), t0 = at<NC>(tau, k), t = t0 + theta * dk;
    const double m = t.norm();
    if (i >= nslip) {  // a stick node's force correction; over its bound it starts to slip
      const Vec<NC> y = m > g(k) ? Vec<NC>(t * (g(k) / m)) : t;
      if (m > g(k)) {
        released = true;  // the stick set changed
        back.push_back(k);
        for (int c = 0; c < NC; ++c) w.back_val[c].push_back(y(c) - t(c));
      }
      put<NC>(tau, k, y);
      continue;
    }
    const Vec<NC> full = t0 + dk;
    const bool turn = full.norm() >= g(k) * (1.0 - kBoundEps) && full.dot(t0) > 0.0;
    if (turn && m > 0.0 && m < g(k)) {
      const Vec<NC> y = t * (g(k) / m);
      back.push_back(k);
      for (int c = 0; c < NC; ++c) w.back_val[c].push_back(y(c) - t(c));
      put<NC>(tau, k, y);
    } else {
      put<NC>(tau, k, t);
      released |= m < g(k) * (1.0 - kBoundEps);
    }
  }
  w.op.add_sparse(back, w.back_val, tau, u);
  clear_step();
  return released;
}

// The CG step tau += alpha d, u += alpha q on the contact nodes, fused with the projection of
// the stick nodes that it carried out of their disc (they start to slip).
template <int NC>
bool step_and_project_impl(Workspace& w, double alpha, const VecField& d, const VecField& q,
                           VecField& tau, VecField& u) {
  const Field& g = *w.inc.bound;
  const NodeSets& sets = w.sets;
  w.idx.clear();
  for (auto& v : w.val) v.clear();
  for (std::size_t j = 0; j < sets.contact.size(); ++j) {
    const Eigen::Index k = sets.contact[j];
    if (alpha != 0.0)
      for (int c = 0; c < NC; ++c) tau[c](k) += alpha * d[c](k), u[c](k) += alpha * q[c](k);
    if (!sets.stick[j]) continue;
    const Vec<NC> t = at<NC>(tau, k);
    const double m = t.norm();
    if (m <= g(k)) continue;
    const Vec<NC> y = t * (g(k) / m);
    w.idx.push_back(k);
    for (int c = 0; c < NC; ++c) w.val[c].push_back(y(c) - t(c));
    put<NC>(tau, k, y);
  }
  // u on the contact nodes only: the projected solver reads nothing else, and it ends on an
  // exact product (its verification) that sets u everywhere.
  w.op.add_sparse_at(w.idx, w.val, tau, sets.contact, u);
  return !w.idx.empty();
}

}  // namespace

ForceShift Workspace::shift_to_force(bool all, const Eigen::VectorXd& want, VecField& tau) const {
  return by_components(int(tau.size()), [&](auto nc) {
    return shift_to_force_impl<decltype(nc)::value>(sets, *inc.bound, gsum, all, want, tau);
  });
}

bool Workspace::slip_node_step(VecField& tau, VecField& u, bool carry_force) {
  return by_components(op.components(), [&](auto nc) {
    return slip_node_step_impl<decltype(nc)::value>(*this, tau, u, carry_force);
  });
}

bool Workspace::step_and_project(double alpha, const VecField& d, const VecField& q, VecField& tau,
                                 VecField& u) {
  bool set_changed = by_components(op.components(), [&](auto nc) {
    return step_and_project_impl<decltype(nc)::value>(*this, alpha, d, q, tau, u);
  });
  set_changed |= slip_node_step(tau, u);
  if (inc.control == TangentialControl::force) restore_force(tau, u);
  return set_changed;
}

TangentialResult Workspace::finish(const VecField& tau, const std::string& algorithm) {
  result.convolutions = int(op.half_space().convolutions() - conv0);
  result.force = total_force(tau, op.grid());
  if (!result.converged) {
    std::ostringstream msg;
    msg << algorithm << " tangential solver did not converge: residual " << result.residual
        << " > tolerance " << opt.tolerance << " after " << result.iterations << " iterations";
    throw SolverError(msg.str());
  }
  return result;
}

}  // namespace fretbem::tangential_detail
