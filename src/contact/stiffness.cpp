#include "fretbem/contact/stiffness.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>

#include "fretbem/contact/cg_core.hpp"
#include "fretbem/core/errors.hpp"
#include "slab_preconditioning.hpp"

namespace fretbem {

namespace {

// Recently solved stick sets kept for reuse: a cycle meets the full contact (after each
// reversal) and the turning-point sets of both signs; a periodic history started from the
// previous cycle's solution (solver.predictor = cycle) meets a whole cycle of sets again. 160
// covers a cycle of up to 160 steps at 20 bytes per cell at most (one bit per node and set).
constexpr std::size_t kKnownSets = 160;

std::vector<std::uint64_t> pack(const std::vector<std::uint8_t>& flags) {
  std::vector<std::uint64_t> bits((flags.size() + 63) / 64, 0);
  for (std::size_t k = 0; k < flags.size(); ++k)
    if (flags[k]) bits[k / 64] |= std::uint64_t(1) << (k % 64);
  return bits;
}

// Stopping rule on the value k_x rather than on the residual. CG raises J monotonically and
// its error is the sum of the remaining increments (Hestenes-Stiefel; Strakos & Tichy, ETNA 13,
// 2002). The remainder is extrapolated geometrically from the slowest of the last kWindow
// increment ratios, so a plateau (ratio near 1) keeps the solve going; the solve stops when
// that remainder is below kShare * tol of J. kShare: the shipped tolerances leave k_x within
// 0.1 tol of a tight solve (tests/test_stiffness.cpp, StiffnessEnergyStop).
class KxEstimate {
 public:
  explicit KxEstimate(double tol) : tol_(tol) {}
  void add(double J) {
    if (count_ > 0) {
      const double inc = J - last_;
      if (count_ > 1) ratios_[(count_ - 2) % kWindow] = prev_inc_ > 0 ? inc / prev_inc_ : 1.0;
      prev_inc_ = inc;
    }
    last_ = J, ++count_;
  }
  bool converged() const { return error() <= kShare * tol_; }
  double value() const { return last_; }
  /// The extrapolated remainder relative to J (infinite before the window is full).
  double error() const {
    if (count_ < kWindow + 2 || !(last_ > 0)) return std::numeric_limits<double>::infinity();
    double rho = 0.0;
    for (const double r : ratios_) rho = std::max(rho, r);
    return rho < 1.0 ? std::max(prev_inc_, 0.0) * rho / (1.0 - rho) / last_
                     : std::numeric_limits<double>::infinity();
  }

 private:
  static constexpr int kWindow = 4;
  static constexpr double kShare = 0.1;
  double tol_, last_ = 0.0, prev_inc_ = 0.0;
  double ratios_[kWindow] = {};
  int count_ = 0;
};

// Every node stuck on a periodic grid: the periodic kernels have no mean mode (displacements
// are measured from their mean, half_space_kernels.cpp), and the unit shift e_x on all nodes is
// that mode. C psi = e_x has no solution and J = sup (2 e_x.psi - psi.C psi) grows without bound
// along psi = t e_x: the interface adds no compliance, k_x = +inf exactly.
StiffnessResult rigid_interface(StiffnessResult res) {
  res.kx = std::numeric_limits<double>::infinity();
  return res;
}

}  // namespace

StiffnessSolver::StiffnessSolver(TangentialOperator& op, double tolerance, int max_iterations,
                                 Precondition precondition)
    : op_(op), tol_(tolerance), max_it_(max_iterations), preconditioning_(precondition) {
  op_.half_space().require_tolerance(tol_, "stiffness solver");
}

// psi_ restricted to the new stick set, and u_ = C psi_ brought along: the nodes that left the
// set lose their psi by a sparse direct-sum update when they are few (a stick set shrinking
// under monotone loading), by one product otherwise. Nodes that joined start from zero.
void StiffnessSolver::warm_start(const std::vector<std::uint8_t>& stick) {
  const int nc = op_.components();
  if (psi_.size() != std::size_t(nc)) {
    psi_ = op_.zeros(), u_ = op_.zeros();
    psi_set_.assign(stick.size(), 0);
  }
  std::vector<std::int64_t> idx;
  std::vector<std::vector<double>> val(nc);
  for (std::size_t k = 0; k < stick.size(); ++k) {
    if (!psi_set_[k] || stick[k]) continue;
    bool nonzero = false;
    for (int c = 0; c < nc; ++c) nonzero |= psi_[c](Eigen::Index(k)) != 0.0;
    if (!nonzero) continue;
    idx.push_back(std::int64_t(k));
    for (int c = 0; c < nc; ++c) {
      val[c].push_back(-psi_[c](Eigen::Index(k)));
      psi_[c](Eigen::Index(k)) = 0.0;
    }
  }
  // Incremental updates drift by round-off; an exact product every so often bounds it.
  if (++solves_ % 32 == 0)
    op_.apply(psi_, u_);
  else
    op_.add_sparse(idx, val, psi_, u_);
  psi_set_ = stick;
}

// CG for C psi = e_x on the stick nodes as a cg::run problem: an unconstrained linear solve,
// stopped on the energy value rather than confirmed on an exact product.
class StiffnessSolver::Iteration {
 public:
  // nstick: the stick nodes on all ranks.
  Iteration(StiffnessSolver& s, bool pre, KxEstimate& est, std::size_t nstick)
      : s_(s), comm_(s.op_.half_space().communicator()), pre_(pre), est_(est), nstick_(nstick) {}

  // Residual r = S (e_x - C psi): a unit shift along x (component 0 in both bases).
  double residual() {
    const int nc = s_.op_.components();
    double rr = 0.0, psi_r = 0.0, b_psi = 0.0;
    for (const Eigen::Index k : s_.nodes_)
      for (int c = 0; c < nc; ++c) {
        const double r = (c == 0 ? 1.0 : 0.0) - s_.u_[c](k);
        s_.r_[c](k) = r, rr += r * r, psi_r += s_.psi_[c](k) * r;
      }
    for (const Eigen::Index k : s_.nodes_) b_psi += s_.psi_[0](k);  // e_x . psi
    std::array<double, 3> sums{rr, psi_r, b_psi};
    comm_.sum(sums);
    rr = sums[0], psi_r = sums[1], b_psi = sums[2];
    rr_ = rr;
    // The energy value J = 2 b.psi - psi.C psi = b.psi + psi.r (b = e_x on S): its error
    // against b.C^-1 b is e.C e, quadratic in the CG error, where b.psi is linear in it.
    est_.add(b_psi + psi_r);
    return std::sqrt(rr) / std::sqrt(double(nstick_));
  }
  cg::Next on_residual(int, const cg::Watch&) const { return cg::Next::proceed; }
  void refresh() {}
  bool exhausted(int it, const cg::Watch&) const { return est_.converged() || it >= s_.max_it_; }

  // Preconditioned CG (Vollebregt, J. Comput. Phys. 257, 2014): z = S K_z^-1 r; the analogy
  // operator is (E*/G*) K_z and CG is blind to the factor; for Cerruti K_z^-1 per component
  // is a spectrally equivalent SPD approximation (as in ProjectedCgSolver).
  double gradient_product() {
    G_ = rr_;
    if (pre_) {
      const int nc = s_.op_.components();
      G_ = 0.0;
      for (int c = 0; c < nc; ++c) s_.op_.half_space().normal_inverse(s_.r_[c], s_.z_[c]);
      for (const Eigen::Index k : s_.nodes_)
        for (int c = 0; c < nc; ++c) G_ += s_.r_[c](k) * s_.z_[c](k);
      G_ = comm_.sum(G_);
    }
    return G_;
  }

  cg::Step step(double beta) {
    const int nc = s_.op_.components();
    VecField &d = s_.d_, &q = s_.q_;
    const VecField& z = pre_ ? s_.z_ : s_.r_;
    for (const Eigen::Index k : s_.nodes_)
      for (int c = 0; c < nc; ++c) d[c](k) = z[c](k) + beta * d[c](k);
    s_.op_.apply(d, q);
    double den = 0.0;
    for (const Eigen::Index k : s_.nodes_)
      for (int c = 0; c < nc; ++c) den += q[c](k) * d[c](k);
    den = comm_.sum(den);
    if (!(den > 0.0) || !(G_ > 0.0)) return {cg::Next::stop};
    const double alpha = G_ / den;
    for (const Eigen::Index k : s_.nodes_)
      for (int c = 0; c < nc; ++c) s_.psi_[c](k) += alpha * d[c](k);
    // u_ on the whole grid: the next step's stick set may reach beyond this one.
    for (int c = 0; c < nc; ++c) s_.u_[c] += alpha * q[c];
    return {cg::Next::proceed, false};
  }

 private:
  StiffnessSolver& s_;
  const Communicator& comm_;  // the grid's reduction layer: every sum over stick nodes
  const bool pre_;
  KxEstimate& est_;
  const std::size_t nstick_;
  double rr_ = 0.0, G_ = 0.0;
};

// psi_ = start on the stick nodes (zero elsewhere and in the other component), u_ = C psi_.
void StiffnessSolver::given_start(const std::vector<std::uint8_t>& stick, const Field& start) {
  psi_ = op_.zeros(), u_ = op_.zeros();
  for (const Eigen::Index k : nodes_) psi_[0](k) = start(k);
  op_.apply(psi_, u_);
  psi_set_ = stick;
}

StiffnessResult StiffnessSolver::solve(const StateField& state, const Field* start) {
  StiffnessResult res;
  solved_ = false;
  std::vector<std::uint8_t> stick(std::size_t(state.size()));
  nodes_.clear();
  for (Eigen::Index k = 0; k < state.size(); ++k) {
    stick[std::size_t(k)] = state(k) == std::uint8_t(NodeState::stick);
    if (stick[std::size_t(k)]) nodes_.push_back(k);
  }
  // Counts over all ranks; on a distributed grid `state` and the lists are this rank's slab.
  const Communicator& comm = op_.half_space().communicator();
  const auto nstick = std::size_t(comm.sum(double(nodes_.size())));
  if (nstick == 0) return res;  // full sliding: no stiffness
  if (op_.grid().periodic && nstick == op_.grid().size()) return rigid_interface(res);
  // k_x depends on the stick set alone: a set met recently (an unchanged step, the full
  // contact after a reversal) needs no new solve.
  const std::vector<std::uint64_t> bits = pack(stick);
  const bool given = start && start->size() == state.size();
  for (const Known& kn : known_)
    if (!given && comm.min(kn.count == nstick && kn.stick == bits ? 1.0 : 0.0) > 0.0) {
      res.kx = kn.kx;
      res.reused = true;
      return res;
    }
  if (given)
    given_start(stick, *start);
  else
    warm_start(stick);
  auto stick_set = [&] {
    Field set(state.rows(), state.cols());
    for (Eigen::Index k = 0; k < set.size(); ++k) set(k) = stick[std::size_t(k)];
    return set;
  };
  const bool pre = res.preconditioned =
      comm.distributed() ? for_distributed_set(preconditioning_, stick_set(), op_.grid(), comm)
                         : preconditioning_.for_nodes(nodes_, stick_set);
  // r_ and d_ are zero off the stick set: the preconditioner and the product read them whole.
  r_ = op_.zeros(), d_ = op_.zeros();
  if (pre) z_.resize(op_.components());
  KxEstimate est(tol_);
  Iteration iteration(*this, pre, est, nstick);
  cg::Rules rules;
  rules.tolerance = tol_;
  rules.verify = false;
  const cg::Outcome out = cg::run(iteration, rules);
  res.iterations = out.iterations;
  res.residual = out.residual;
  if (!(res.residual <= tol_) && !est.converged()) {
    std::ostringstream msg;
    msg << "stiffness solve did not converge: residual " << res.residual << " after "
        << res.iterations << " iterations";
    throw SolverError(msg.str());
  }
  res.kx = est.value() * op_.grid().cell_area();
  res.kx_error = est.error();
  solved_ = true;
  known_.push_front({nstick, bits, res.kx});
  if (known_.size() > kKnownSets) known_.pop_back();
  return res;
}

}  // namespace fretbem
