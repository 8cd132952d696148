#include "fretbem/contact/tangential_solver.hpp"

#include <cmath>
#include <limits>
#include <span>
#include <type_traits>

#include "fretbem/contact/cg_core.hpp"
#include "slab_preconditioning.hpp"
#include "workspace.hpp"

namespace fretbem {

using namespace tangential_detail;

double coulomb_residual(const Grid& grid, const TangentialIncrement& inc, const VecField& tau,
                        const VecField& u, double scale, Eigen::VectorXd& dU, VecField& s,
                        const Communicator& comm) {
  NodeSets sets(*inc.bound, comm);
  double stick_slip2 = 0.0;
  const double res = residual(sets, inc, tau, u, scale, grid, dU, stick_slip2);
  s.resize(tau.size());
  for (std::size_t c = 0; c < tau.size(); ++c) s[c] = dU(c) - (u[c] - (*inc.u0)[c]);
  return res;
}

ProjectedCgSolver::ProjectedCgSolver(TangentialOperator& op, TangentialOptions opt)
    : op_(op),
      opt_(opt),
      preconditioning_(opt.precondition),
      cache_(std::make_unique<BoundCache>()) {
  op_.half_space().require_tolerance(opt_.tolerance, "tangential solver");
}

ProjectedCgSolver::~ProjectedCgSolver() = default;

bool ProjectedCgSolver::preconditioned(const Field& bound) const {
  return preconditioning_.for_set(bound);
}

TangentialResult ProjectedCgSolver::solve(const TangentialIncrement& inc, VecField& tau,
                                          VecField& u) {
  if (op_.components() == 1) return solve_components<1>(inc, tau, u);
  return solve_components<2>(inc, tau, u);
}

namespace {

// Whether an increment on these contact nodes and bound is preconditioned, on every rank.
bool precondition_increment(PreconditionDecision& decision, TangentialOperator& op,
                            const std::vector<Eigen::Index>& contact, const Field& bound) {
  const Communicator& comm = op.half_space().communicator();
  if (comm.distributed()) return for_distributed_set(decision, bound, op.grid(), comm);
  return decision.for_nodes(contact, [&]() -> const Field& { return bound; });
}

// The CG step tau += alpha d, u += alpha q on the contact nodes, fused with the projection of
// the stick nodes that it carried out of their disc (they start to slip).
template <int NC>
bool step_and_project(Workspace& w, double alpha, const VecField& d, const VecField& q,
                      VecField& tau, VecField& u) {
  const Field& g = *w.inc.bound;
  const NodeSets& sets = w.sets;
  w.slip.idx.clear();
  for (auto& v : w.slip.val) v.clear();
  for (std::size_t j = 0; j < sets.contact.size(); ++j) {
    const Eigen::Index k = sets.contact[j];
    if (alpha != 0.0)
      for (int c = 0; c < NC; ++c) tau[c](k) += alpha * d[c](k), u[c](k) += alpha * q[c](k);
    if (!sets.stick[j]) continue;
    const Vec<NC> t = at<NC>(tau, k);
    const double m = t.norm();
    if (m <= g(k)) continue;
    const Vec<NC> y = t * (g(k) / m);
    w.slip.idx.push_back(k);
    for (int c = 0; c < NC; ++c) w.slip.val[c].push_back(y(c) - t(c));
    put<NC>(tau, k, y);
  }
  // u on the contact nodes only: the projected solver reads nothing else, and it ends on an
  // exact product (its verification) that sets u everywhere.
  w.op.add_sparse_at(w.slip.idx, w.slip.val, tau, sets.contact, u);
  return w.comm().any(!w.slip.idx.empty());
}

}  // namespace

// Residual growth by this factor within one iteration restarts conjugacy. CG on a fixed set
// does not keep the residual monotone, but a doubling in one step signals a change from
// outside its recurrence (u recomputed, a force correction, nodes released or put back):
// continuing with beta = G / g_old ~ 1e10 after such a jump made the iteration crawl.
constexpr double kResidualJump = 2.0;
// No new best residual for this many iterations: hand over to the fallbacks now rather than
// after max_iterations (measured: a diverging force-controlled increment cycled with period
// ~1500 iterations between residuals 0.39 and 0.62).
constexpr int kStagnation = 1000;
// A step raises the QP objective when it exceeds the start by more than this fraction of it
// (the round-off of the incremental u and of the force redistribution stays far below).
constexpr double kObjectiveRoundoff = 1e-12;

// CG on the stick set as a cg::run problem. The QP's gradient is -s; under force control s
// has zero mean on the stick set (dU is that mean), so the directions keep the total force.
// After each step the Workspace projects stick nodes that left their disc, moves the slip
// nodes and restores the force.
template <int NC>
class ProjectedCgSolver::Iteration {
  using Vec = Eigen::Matrix<double, NC, 1>;

 public:
  Iteration(ProjectedCgSolver& s, Workspace& w, bool pre, VecField& tau, VecField& u)
      : s_(s), w_(w), pre_(pre), tau_(tau), u_(u) {}

  double residual() {  // classifies the stick set S
    if (w_.start_residual) {
      const auto [res, stick_slip2] = *w_.start_residual;
      w_.start_residual.reset();
      G_ = stick_slip2;
      return w_.result.residual = res;
    }
    w_.result.residual = w_.residual(tau_, u_, G_);
    return w_.result.residual;
  }
  cg::Next on_residual(int, const cg::Watch&) const { return cg::Next::proceed; }
  void refresh() {
    s_.op_.apply(tau_, u_);
    objective_known_ = false;
  }
  bool exhausted(int it, const cg::Watch& w) const {
    return it >= s_.opt_.max_iterations || it - w.best_it > kStagnation;
  }

  // G = s . s on S (from the residual), or s . z with the preconditioned z.
  double gradient_product() {
    if (!buffers_) make_buffers();
    zbar_ = Vec::Zero();
    if (pre_ && w_.sets.nstick > 0) G_ = preconditioned_product();
    return G_;
  }

  // The CG step on S with the projection of the nodes it carries out of their disc, then the
  // slip nodes' line-searched step and the force redistribution (force control). Projection
  // and redistribution are not steps of a line search and can raise the QP objective; when
  // they do, the iteration can cycle (measured: coupled normal ramp, beta/mu = 4, 3 of 44
  // nodes sticking at zero force: a 2-cycle between 3 and 23 stick nodes, residual 0.51/0.79).
  // Such a step is taken again as a feasible one (no node leaves its disc: MPRGP's feasible
  // step, Dostal, Optimal quadratic programming algorithms, 2009, ch. 5), which lowers the
  // objective, so the iteration cannot return to an earlier iterate.
  cg::Step step(double beta) {
    const double num = direction(beta);
    double alpha = 0.0;
    if (G_ > 0.0) {
      s_.op_.apply(s_.d_, s_.q_);
      const double den = curvature();
      // No curvature along a descent direction (the mean mode of a periodic grid, whose
      // kernels have none: a uniform traction moves nothing): the objective falls linearly,
      // so the step goes as far as the stick nodes' discs allow.
      if (den > 0.0)
        alpha = num / den;
      else if (num > 0.0)
        alpha = feasible_step();
    }
    save_iterate();
    bool changed = projected_step(alpha, false);
    const double after = objective();
    objective_known_ = true, known_objective_ = after;
    if (after > saved_objective_ + kObjectiveRoundoff * std::abs(saved_objective_)) {
      restore_iterate();
      projected_step(std::min(alpha, feasible_step()), true);
      changed = true;
      objective_known_ = false;
    }
    return {cg::Next::proceed, changed || !(alpha > 0.0)};
  }

 private:
  bool projected_step(double alpha, bool feasible) {
    bool changed = step_and_project<NC>(w_, alpha, s_.d_, s_.q_, tau_, u_);
    changed |= w_.slip_node_step(tau_, u_, true, feasible);
    if (w_.inc.control == TangentialControl::force) w_.restore_force(tau_, u_);
    return changed;
  }

  // The QP objective 1/2 dtau . (u - u0) - dU . sum dtau over the contact nodes (off contact
  // tau = tau0 = 0); under force control sum dtau is fixed and the dU term is left out.
  double objective() const {
    const VecField &t0 = *w_.inc.tau0, &u0 = *w_.inc.u0;
    const bool shift = w_.inc.control == TangentialControl::displacement;
    double e = 0.0;
    for (const Eigen::Index k : w_.sets.contact)
      for (int c = 0; c < NC; ++c) {
        const double dt = tau_[c](k) - t0[c](k);
        e += dt * (0.5 * (u_[c](k) - u0[c](k)) - (shift ? w_.inc.target(c) : 0.0));
      }
    return w_.comm().sum(e);
  }

  // tau and u on the contact nodes (all the iteration reads) and the stick set, before a step.
  void save_iterate() {
    const auto& contact = w_.sets.contact;
    saved_.resize(2 * NC * contact.size());
    for (std::size_t j = 0; j < contact.size(); ++j)
      for (int c = 0; c < NC; ++c) {
        saved_[2 * NC * j + c] = tau_[c](contact[j]);
        saved_[2 * NC * j + NC + c] = u_[c](contact[j]);
      }
    saved_stick_ = w_.sets.stick;
    saved_nstick_ = w_.sets.nstick;
    // The last step's objective where nothing moved tau or u since (one pass fewer a step).
    saved_objective_ = objective_known_ ? known_objective_ : objective();
  }

  void restore_iterate() {
    const auto& contact = w_.sets.contact;
    for (std::size_t j = 0; j < contact.size(); ++j)
      for (int c = 0; c < NC; ++c) {
        tau_[c](contact[j]) = saved_[2 * NC * j + c];
        u_[c](contact[j]) = saved_[2 * NC * j + NC + c];
      }
    w_.sets.stick = saved_stick_;
    w_.sets.nstick = saved_nstick_;
  }

  // The largest t with every stick node inside its disc along tau + t d: the root of
  // |tau + t d|^2 = g^2.
  double feasible_step() const {
    const Field& g = *w_.inc.bound;
    double tmax = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < w_.sets.contact.size(); ++j) {
      if (!w_.sets.stick[j]) continue;
      const Eigen::Index k = w_.sets.contact[j];
      tmax = std::min(tmax, step_to_bound<NC>(at<NC>(tau_, k), at<NC>(s_.d_, k), g(k)));
    }
    return w_.comm().min(tmax);
  }

  Vec slip(Eigen::Index k) const {
    const Eigen::VectorXd& dU = w_.result.shift;
    Vec s;
    for (int c = 0; c < NC; ++c) s(c) = dU(c) - (u_[c](k) - (*w_.inc.u0)[c](k));
    return s;
  }

  // Preconditioned direction z = S K^-1 (S s): the Fourier inverse of the kernel, as the
  // normal solver's PCG (Vollebregt, J. Comput. Phys. 257, 2014). The analogy operator is
  // (E*/G*) K_z and CG is blind to the constant factor; for Cerruti K_z^-1 per component is a
  // spectrally equivalent SPD approximation. Under force control z is made mean-free on S so
  // that the directions keep the force (s . z is unchanged: s is mean-free on S).
  double preconditioned_product() {
    const auto& contact = w_.sets.contact;
    const auto& stick = w_.sets.stick;
    VecField &r = s_.r_, &z = s_.z_;
    for (std::size_t j = 0; j < contact.size(); ++j) {
      const Vec s = stick[j] ? slip(contact[j]) : Vec::Zero();
      for (int c = 0; c < NC; ++c) r[c](contact[j]) = s(c);
    }
    for (int c = 0; c < NC; ++c) s_.op_.half_space().normal_inverse(r[c], z[c]);
    if (w_.inc.control == TangentialControl::force) {
      for (std::size_t j = 0; j < contact.size(); ++j)
        if (stick[j])
          for (int c = 0; c < NC; ++c) zbar_(c) += z[c](contact[j]);
      w_.comm().sum(std::span<double>(zbar_.data(), NC));
      zbar_ /= double(w_.sets.nstick);
    }
    double G = 0.0;
    for (std::size_t j = 0; j < contact.size(); ++j) {
      if (!stick[j]) continue;
      const Eigen::Index k = contact[j];
      for (int c = 0; c < NC; ++c) G += (r[c](k)) * (z[c](k) - zbar_(c));
    }
    return w_.comm().sum(G);
  }

  // The direction (zero off contact: only contact entries are ever written) and the
  // preconditioner's buffers, made when the first step is taken: a converged start needs none.
  void make_buffers() {
    s_.d_ = s_.op_.zeros();
    if (pre_) s_.r_ = s_.op_.zeros(), s_.z_.resize(NC);
    buffers_ = true;
  }

  // d = z + beta d on S (zero elsewhere); returns s . d.
  double direction(double beta) {
    const auto& contact = w_.sets.contact;
    const auto& stick = w_.sets.stick;
    VecField& d = s_.d_;
    double num = 0.0;
    for (std::size_t j = 0; j < contact.size(); ++j) {
      const Eigen::Index k = contact[j];
      if (!stick[j]) {
        for (int c = 0; c < NC; ++c) d[c](k) = 0.0;
        continue;
      }
      const Vec s = slip(k);
      for (int c = 0; c < NC; ++c) {
        d[c](k) = (pre_ ? s_.z_[c](k) - zbar_(c) : s(c)) + beta * d[c](k);
        num += s(c) * d[c](k);
      }
    }
    return w_.comm().sum(num);
  }

  // d . C d on S, with q made mean-free on S under force control (the multiplier dU absorbs
  // the mean).
  double curvature() const {
    const auto& contact = w_.sets.contact;
    const auto& stick = w_.sets.stick;
    const VecField &d = s_.d_, &q = s_.q_;
    Vec qd = Vec::Zero(), qsum = Vec::Zero(), dsum = Vec::Zero();
    for (std::size_t j = 0; j < contact.size(); ++j) {
      if (!stick[j]) continue;
      const Eigen::Index k = contact[j];
      for (int c = 0; c < NC; ++c)
        qd(c) += q[c](k) * d[c](k), qsum(c) += q[c](k), dsum(c) += d[c](k);
    }
    // One message for the three sums.
    Eigen::Matrix<double, NC, 3> sums;
    sums << qd, qsum, dsum;
    w_.comm().sum(std::span<double>(sums.data(), sums.size()));
    qd = sums.col(0), qsum = sums.col(1), dsum = sums.col(2);
    double den = qd.sum();
    if (w_.inc.control == TangentialControl::force)
      den -= qsum.dot(dsum) / double(std::max<std::int64_t>(1, w_.sets.nstick));
    return den;
  }

  ProjectedCgSolver& s_;
  Workspace& w_;
  const bool pre_;
  bool buffers_ = false;  // make_buffers done
  VecField &tau_, &u_;
  double G_ = 0.0;
  Vec zbar_ = Vec::Zero();     // mean of z on S (force control), subtracted from the direction
  std::vector<double> saved_;  // save_iterate: tau and u per contact node
  std::vector<std::uint8_t> saved_stick_;
  std::int64_t saved_nstick_ = 0;
  double saved_objective_ = 0.0;
  bool objective_known_ = false;  // known_objective_ is the objective of tau_ and u_ now
  double known_objective_ = 0.0;
};

// One threshold for every solve that may end on its updated image (cg_core.hpp).
static_assert(ProjectedCgSolver::kUnverifiedTolerance == cg::kUnverifiedTolerance);

template <int NC>
TangentialResult ProjectedCgSolver::solve_components(const TangentialIncrement& inc, VecField& tau,
                                                     VecField& u) {
  Workspace w(op_, inc, opt_, *cache_);
  w.u_on_contact_only = true;
  w.start(tau, u);
  const bool pre = precondition_increment(preconditioning_, op_, w.sets.contact, *inc.bound);
  Iteration<NC> iteration(*this, w, pre, tau, u);
  cg::Rules rules;
  rules.tolerance = opt_.tolerance;
  // u off contact is read by nobody before the next product (contact_fixed): the verifying
  // product would only confirm a residual that its drift cannot move.
  rules.verify = !(inc.contact_fixed && op_.half_space().min_tolerance() == 0.0 &&
                   opt_.tolerance >= kUnverifiedTolerance);
  // A start imaged by one product needs no verifying product: u = C tau has not drifted yet.
  rules.verified_at_start = w.exact;
  rules.restart_after_verify = true;
  rules.jump = kResidualJump;
  const cg::Outcome out = cg::run(iteration, rules);
  w.result.iterations = out.iterations;
  w.result.converged = out.converged;
  return w.finish(tau, "projected-CG");
}

}  // namespace fretbem
