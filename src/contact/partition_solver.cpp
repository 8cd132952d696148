// The paper's partition iteration (Methods section), kept as the baseline algorithm.
#include <cmath>
#include <limits>

#include "fretbem/contact/cg_core.hpp"
#include "fretbem/contact/tangential_solver.hpp"
#include "workspace.hpp"

namespace fretbem {

using namespace tangential_detail;

namespace {

// Outer iterations without halving the best residual after which the partition is cycling.
constexpr int kStagnantPartitions = 30;

// Conjugate gradients for s = 0 on the stick set with the slip tractions held fixed (under
// force control with the total force held: zero-mean directions), as a cg::run problem: linear,
// stopped on the absolute rms slip without a confirming product.
class StickSetCg {
 public:
  StickSetCg(TangentialOperator& op, const TangentialIncrement& inc, const Field& stick,
             VecField& tau, VecField& u)
      : op_(op), inc_(inc), stick_(stick), tau_(tau), u_(u), s_(op.components()), d_(op.zeros()) {}

  // The rms slip beyond its round-off (kSlipRoundoff): a stick set shifted by |dU| >> |C g|
  // cannot slip less than a few eps |dU|, and CG ran out its iterations trying. One pass over
  // the cells, without temporaries: it runs once per CG iteration.
  double residual() {
    const Eigen::VectorXd dU = shift_estimate(inc_, u_, stick_, comm());
    const int nc = op_.components();
    for (int c = 0; c < nc; ++c) s_[c] = stick_ * (dU(c) - (u_[c] - (*inc_.u0)[c]));
    const double shift = dU.norm();
    double rr = 0.0, net = 0.0;
    for (Eigen::Index k = 0; k < stick_.size(); ++k) {
      if (!(stick_(k) > 0.0)) continue;
      double s2 = 0.0, u2 = 0.0, u02 = 0.0;
      for (int c = 0; c < nc; ++c) {
        s2 += s_[c](k) * s_[c](k);
        u2 += u_[c](k) * u_[c](k);
        u02 += (*inc_.u0)[c](k) * (*inc_.u0)[c](k);
      }
      const double floor = kSlipRoundoff * (shift + std::sqrt(u2) + std::sqrt(u02));
      rr += s2;
      net += std::max(0.0, s2 - floor * floor);
    }
    rr_ = comm().sum(rr);
    return std::sqrt(comm().sum(net) / std::max(1.0, comm().sum(stick_.sum())));
  }
  cg::Next on_residual(int, const cg::Watch&) const { return cg::Next::proceed; }
  void refresh() {}
  bool exhausted(int, const cg::Watch&) const { return false; }
  double gradient_product() const { return rr_; }

  cg::Step step(double beta) {
    const int nc = op_.components();
    for (int c = 0; c < nc; ++c) d_[c] = s_[c] + beta * d_[c];
    op_.apply(d_, q_);
    double den = 0.0;
    const double nstick = comm().sum(stick_.sum());
    for (int c = 0; c < nc; ++c) {
      const double qbar = inc_.control == TangentialControl::force
                              ? comm().sum((stick_ * q_[c]).sum()) / nstick
                              : 0.0;
      den += comm().sum((stick_ * (q_[c] - qbar) * d_[c]).sum());
    }
    if (!(den > 0.0)) {
      stopped_ = true;
      return {cg::Next::stop};
    }
    const double alpha = rr_ / den;
    for (int c = 0; c < nc; ++c) tau_[c] += alpha * d_[c], u_[c] += alpha * q_[c];
    return {cg::Next::proceed, false};
  }
  bool stopped() const { return stopped_; }

 private:
  const Communicator& comm() const { return op_.half_space().communicator(); }

  TangentialOperator& op_;
  const TangentialIncrement& inc_;
  const Field& stick_;
  VecField &tau_, &u_;
  VecField s_, d_, q_;
  double rr_ = 0.0;
  bool stopped_ = false;
};

// Runs StickSetCg for at most max_it iterations; returns the iterations used.
int solve_stick_set(TangentialOperator& op, const TangentialIncrement& inc, const Field& stick,
                    double tol_abs, int max_it, VecField& tau, VecField& u) {
  StickSetCg stick_cg(op, inc, stick, tau, u);
  cg::Rules rules;
  rules.tolerance = tol_abs;
  rules.verify = false;
  rules.last_pass = max_it - 1;
  const cg::Outcome out = cg::run(stick_cg, rules);
  return out.converged || stick_cg.stopped() ? out.iterations : max_it;
}

// Moves nodes across the partition. Slip nodes first, by the projected method's slip-node
// step (Workspace::slip_node_step): the local Newton step y = P(tau + s / C_ii) of every slip
// node with an exact line search on the QP; nodes that re-enter their disc stick again. Then
// stick nodes over their bound start to slip, projected radially onto it. Returns the number
// of nodes moved.
//
// The line search keeps the partition from cycling under Cerruti's x-y coupling: an undamped
// simultaneous step tau + s / C_ii would be a Jacobi iteration on the slip directions, and Jacobi
// on the dense Boussinesq/Cerruti kernel overshoots every smooth mode (the off-diagonal row sum
// over a slip ring exceeds C_ii many times). Under the analogy at 0 degrees a slip direction is a
// sign, so the overshoot is cut off by the bound and harmless; under Cerruti the y-traction of the
// slip ring rotates, the overshoot swings it from side to side, and nodes whose slip swings
// backwards fall in and out of the stick set (measured: 4-7 nodes cycling, residual ~0.25 for 5000
// iterations).
int repartition(Workspace& w, Field& stick, VecField& tau, VecField& u) {
  const Field& g = *w.inc.bound;
  NodeSets& sets = w.sets;
  for (std::size_t j = 0; j < sets.contact.size(); ++j)
    sets.stick[j] = stick(sets.contact[j]) > 0.0;
  sets.count_stick();
  w.slip_node_step(tau, u, false);  // the stick solve that follows restores the force
  const int nc = int(tau.size());
  int moved = 0;
  for (std::size_t j = 0; j < sets.contact.size(); ++j) {
    const Eigen::Index k = sets.contact[j];
    double m2 = 0.0;
    for (int c = 0; c < nc; ++c) m2 += tau[c](k) * tau[c](k);
    const double m = std::sqrt(m2);
    if (sets.stick[j]) {
      if (m <= g(k)) continue;
      stick(k) = 0.0, ++moved;  // over its bound: it slips
      for (int c = 0; c < nc; ++c) tau[c](k) *= g(k) / m;
    } else if (m < g(k) * (1.0 - kBoundEps)) {
      stick(k) = 1.0, ++moved;  // slipping backwards: re-entered its disc, it sticks
    }
  }
  return int(w.comm().sum(double(moved)));
}

}  // namespace

PartitionSolver::PartitionSolver(TangentialOperator& op, TangentialOptions opt)
    : op_(op), opt_(opt), cache_(std::make_unique<BoundCache>()) {
  op_.half_space().require_tolerance(opt_.tolerance, "tangential solver");
}

PartitionSolver::~PartitionSolver() = default;

TangentialResult PartitionSolver::solve(const TangentialIncrement& inc, VecField& tau,
                                        VecField& u) {
  Workspace w(op_, inc, opt_, *cache_);
  w.start(tau, u);
  Field stick = free_mask(*inc.bound, magnitude(tau));
  VecField s;
  int used = 0, outer = 0, best_outer = 0;
  double best = std::numeric_limits<double>::infinity();
  while (used < opt_.max_iterations) {
    used += solve_stick_set(op_, inc, stick, opt_.tolerance * w.scale, opt_.max_iterations - used,
                            tau, u);
    const int moved = repartition(w, stick, tau, u);
    op_.apply(tau, u), ++used;
    w.restore_force(tau, u);
    w.result.residual =
        coulomb_residual(op_.grid(), inc, tau, u, w.scale, w.result.shift, s, w.comm());
    if (moved == 0 && w.result.residual <= opt_.tolerance) {
      w.result.converged = true;
      break;
    }
    // A partition that cycles does not come back: stop and report, so that
    // FallbackTangentialSolver hands the increment to the projected method at once (a safety
    // net: the Cerruti cycling that needed it is fixed in repartition).
    if (w.result.residual < 0.5 * best) best = w.result.residual, best_outer = outer;
    if (++outer - best_outer > kStagnantPartitions) break;
  }
  w.result.iterations = used;
  return w.finish(tau, "partition");
}

}  // namespace fretbem
