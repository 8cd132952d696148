#include "fretbem/contact/normal_solver.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <vector>

#include "fretbem/contact/cg_core.hpp"
#include "fretbem/contact/preconditioning.hpp"
#include "fretbem/core/errors.hpp"

namespace fretbem {

namespace {
// Fraction of the contact set whose leaving in one iteration restarts conjugacy.
constexpr double kBulkExit = 0.01;
// Cold start (once) when the residual exceeds the best so far by this factor, or has not
// improved on it for this many iterations.
constexpr double kGrowth = 100.0;
constexpr int kStagnation = 200;

// Sum over every node of the grid (this rank's slab on a distributed one): every global sum
// of the solve goes through the half-space's communicator.
template <class Expr>
double total(const HalfSpace& hs, const Expr& e) {
  return hs.communicator().sum(e.sum());
}

// z = S K^-1 (S g), mean-free on S under force control so that directions keep the force (g is
// mean-free on S there, so g . z is unchanged by the shift).
const Field& preconditioned_direction(HalfSpace& hs, const Eigen::ArrayXXd& S, const Field& g,
                                      bool force_control, Field& z) {
  hs.normal_inverse(S * g, z);
  z *= S;
  if (force_control) z -= S * (total(hs, S * z) / std::max(1.0, total(hs, S)));
  return z;
}

// p holds a warm start: a slab of this rank's shape with a positive value on some rank.
bool is_warm(const HalfSpace& hs, const Field& p) {
  const bool shaped = p.rows() == hs.grid().nx && p.cols() == hs.local_rows();
  const Communicator& c = hs.communicator();
  return c.min(shaped ? 1.0 : 0.0) > 0.0 && c.any(shaped && (p > 0).any());
}
}  // namespace

NormalSolver::NormalSolver(HalfSpace& half_space, NormalOptions options)
    : hs_(half_space), opt_(options) {
  hs_.require_tolerance(opt_.tolerance, "normal solver");
}

NormalResult NormalSolver::solve_force(const Field& z, double force, Field& p) {
  return solve(z, true, force, p);
}

NormalResult NormalSolver::solve_indentation(const Field& z, double delta, Field& p) {
  // A periodic load on a half-space has an unbounded mean displacement: the periodic kernel
  // drops the mean mode, so an approach does not fix the force there (measured: the force
  // returned by solve_force is not recovered). Force control only.
  if (hs_.grid().periodic)
    throw InputError(
        "indentation control is not defined on periodic grids (grid.periodic = "
        "true): use load.normal_force");
  return solve(z, false, delta, p);
}

// Start: the warm start scaled to the target force, else a uniform pressure (PK's choice);
// under indentation control a Winkler guess p = (delta - h0)+ / K(0,0).
void NormalSolver::initial_guess(bool force_control, double target, Field& p) const {
  const Grid& g = hs_.grid();
  const bool warm = is_warm(hs_, p);
  if (force_control) {
    if (warm) {
      p = p.max(0.0);
      p *= target / (total(hs_, p) * g.cell_area());
    } else {
      p = Field::Constant(g.nx, hs_.local_rows(), target / (g.size() * g.cell_area()));
    }
  } else if (!warm) {
    p = ((target - h0_) / hs_.normal_self()).max(0.0);
  }
}

// Polonsky–Keer's conjugate gradient on the contact set S = {p > 0} as a cg::run problem: the
// gap is the residual, the direction lives on S, and after each step p is projected onto
// p >= 0 with penetrating nodes re-entering the contact set.
// Work beside the product: whole-grid expressions made some 25 passes over the grid an
// iteration (perf of an ensemble member: ~23 % of its CPU against ~58 % in the transforms).
// Here one pass over the grid (two under force control) updates u, forms the gap and lists S
// and the penetrating nodes; every other sum, the direction and the projection run over those
// lists, which on a rough contact hold a few per cent of the grid.
class NormalSolver::Iteration {
 public:
  Iteration(NormalSolver& s, bool force_control, double target, Field& p, bool warm)
      : s_(s), hs_(s.hs_), force_control_(force_control), target_(target), p_(p), cold_(!warm) {
    const PreconditionDecision decision(s.opt_.precondition);
    const bool by_set = s.opt_.precondition_by_set && warm && !hs_.communicator().distributed();
    pre_ = by_set ? decision.for_set((p_ > 0.0).cast<double>()) : decision.for_grid(hs_.grid());
  }

  // Relative KKT residual: rms gap on S and rms penetration off S, over the rms displacement on
  // S. Under force control delta is the multiplier that makes the mean gap on S vanish.
  double residual() {
    gap_pass();
    const Communicator& comm = hs_.communicator();
    const Field &g = s_.g_, &u = s_.u_, &h0 = s_.h0_;
    std::array<double, 4> sums{double(on_.size()), 0.0, 0.0, 0.0};  // count, g.g, u.u, h0
    for (const Eigen::Index k : on_)
      sums[1] += g(k) * g(k), sums[2] += u(k) * u(k), sums[3] += h0(k);
    comm.sum(sums);
    const double n = std::max(1.0, sums[0]);
    gg_ = sums[1];
    const double h0bar = sums[3] / n;
    double spread = 0.0;
    for (const Eigen::Index k : on_) spread += (h0(k) - h0bar) * (h0(k) - h0bar);
    // Scale: the rms displacement on S, or the rms height variation over S when that is
    // larger. The second matters on periodic grids, where a uniform pressure displaces nothing
    // (the mean mode has zero compliance): the displacement alone would call full contact
    // converged.
    const double scale = std::max(std::sqrt(sums[2] / n), std::sqrt(comm.sum(spread) / n));
    if (!(scale > 0.0)) return residual_ = sums[0] == 0 ? 1.0 : 0.0;
    residual_ = std::sqrt((gg_ + comm.sum(off_)) / n) / scale;
    return residual_;
  }

  // A warm start far from the solution (thousands of nodes to leave a worn annulus) can make
  // the iteration climb or stall; the cold start does not depend on it. From the cold start,
  // plain Polonsky–Keer can cycle on a worn conforming annulus (measured: n = 32, Q = 0.9 mu P,
  // contact sets of 468 -> 268 -> 132 -> 468 nodes, residual 0.11 -> 0.023 -> 0.016, period 3,
  // for 5000 iterations); the preconditioned direction S K^-1 S g converged there in 17
  // iterations: it is the last resort.
  cg::Next on_residual(int it, const cg::Watch& w) {
    const bool stalled = w.last > kGrowth * w.best || it - w.best_it > kStagnation;
    if (!stalled || (cold_ && (forced_ || pre_))) return cg::Next::proceed;
    forced_ = cold_;
    cold_start();
    return cg::Next::restart;
  }

  // Drops accumulated round-off of the incremental updates before the residual is re-checked.
  void refresh() {
    hs_.normal(p_, s_.u_);
    pending_ = false;
  }
  bool exhausted(int it, const cg::Watch&) const { return it == s_.opt_.max_iterations; }

  // G = g . z on S, z the gap itself (Polonsky–Keer) or the preconditioned z = S K^-1 (S g).
  double gradient_product() {
    if (!(forced_ || pre_)) {
      direction_ = &s_.g_;
      return gg_;
    }
    S_ = (p_ > 0.0).cast<double>();
    direction_ = &preconditioned_direction(hs_, S_, s_.g_, force_control_, s_.z_);
    double G = 0.0;
    for (const Eigen::Index k : on_) G += s_.g_(k) * s_.z_(k);
    return hs_.communicator().sum(G);
  }

  cg::Step step(double beta) {
    Field &t = s_.t_, &r = s_.r_;
    const Field &g = s_.g_, &dir = *direction_;
    // t = S (z + beta t): the new values first, then t cleared on the previous S.
    next_t_.resize(on_.size());
    for (std::size_t i = 0; i < on_.size(); ++i) next_t_[i] = dir(on_[i]) + beta * t(on_[i]);
    for (const Eigen::Index k : t_on_) t(k) = 0.0;
    for (std::size_t i = 0; i < on_.size(); ++i) t(on_[i]) = next_t_[i];
    t_on_ = on_;
    hs_.normal(t, r);
    const Communicator& comm = hs_.communicator();
    double rbar = 0.0;
    if (force_control_) {
      double sr = 0.0;
      for (const Eigen::Index k : on_) sr += r(k);
      rbar = comm.sum(sr) / std::max(1.0, comm.sum(double(on_.size())));
    }
    std::array<double, 2> sums{0.0, 0.0};  // (r - rbar) . t and g . t on S
    for (const Eigen::Index k : on_) sums[0] += (r(k) - rbar) * t(k), sums[1] += g(k) * t(k);
    comm.sum(sums);
    if (!(sums[0] > 0.0)) {
      // No descent on S. At round-off level that is the end; far from it, the warm start's
      // contact set was wrong in a way the iteration cannot leave (e.g. one node, where the
      // mean-free gap on S vanishes): restart once from the cold guess.
      if (cold_ || residual_ < 1e3 * s_.opt_.tolerance) return {cg::Next::stop};
      cold_start();
      return {cg::Next::restart};
    }
    const double tau = sums[1] / sums[0];
    for (const Eigen::Index k : on_) p_(k) -= tau * t(k);
    pending_ = true, pending_tau_ = tau, pending_scale_ = 1.0;  // u -= tau r in the next gap pass
    return {cg::Next::proceed, project(tau)};
  }

  double indentation() const { return delta_; }

  // Brings u up to date with the last step (the loop ends on a residual, which does it).
  void settle() {
    if (!pending_) return;
    Field& u = s_.u_;
    u = (u - pending_tau_ * s_.r_) * pending_scale_;
    pending_ = false;
  }

 private:
  void cold_start() {
    cold_ = true;
    p_ = Field();
    s_.initial_guess(force_control_, target_, p_);
    hs_.normal(p_, s_.u_);
    pending_ = false;
  }

  // The pass over the grid: u <- (u - tau r) scale for the step it owes, the gap
  // g = u + h0 - delta, the list of S, and off S the penetrating nodes and their squared gap.
  void gap_pass() {
    Field &u = s_.u_, &g = s_.g_;
    const Field &h0 = s_.h0_, &r = s_.r_;
    const double tau = pending_ ? pending_tau_ : 0.0, scale = pending_ ? pending_scale_ : 1.0;
    const bool pending = pending_;
    pending_ = false;
    g.resize(p_.rows(), p_.cols());
    on_.clear(), pen_.clear();
    double on_sum = 0.0;
    off_ = 0.0;
    const double delta = force_control_ ? 0.0 : target_;
    for (Eigen::Index k = 0; k < p_.size(); ++k) {
      if (pending) u(k) = (u(k) - tau * r(k)) * scale;
      const double gk = g(k) = u(k) + h0(k) - delta;
      if (p_(k) > 0.0) {
        on_.push_back(k), on_sum += gk;
      } else if (gk < 0.0 && !force_control_) {
        pen_.push_back(k), off_ += gk * gk;
      }
    }
    delta_ = target_;
    if (!force_control_) return;
    const Communicator& comm = hs_.communicator();
    delta_ = comm.sum(on_sum) / std::max(1.0, comm.sum(double(on_.size())));
    for (Eigen::Index k = 0; k < p_.size(); ++k) {
      const double gk = g(k) -= delta_;
      if (gk < 0.0 && !(p_(k) > 0.0)) pen_.push_back(k), off_ += gk * gk;
    }
  }

  // After p <- p - tau t: projection p >= 0 and re-entry of penetrating nodes, whose (sparse)
  // displacement change is added separately; under force control the pressure is rescaled to
  // the force. Returns whether conjugacy restarts.
  bool project(double tau) {
    const Field& g = s_.g_;
    idx_.clear(), val_.clear();
    std::int64_t left = 0;
    auto change = [&](Eigen::Index k, double e) {
      p_(k) += e, idx_.push_back(k), val_.push_back(e);
    };
    for (const Eigen::Index k : on_)
      if (p_(k) < 0.0) change(k, -p_(k)), ++left;
    const bool entered = tau > 0.0 && !pen_.empty();
    if (tau > 0.0)
      for (const Eigen::Index k : pen_) change(k, -tau * g(k));
    // Nodes leaving contact in bulk change S, and with it the problem CG was conjugating on
    // (PK restart only on re-entry; measured: ~3700 annulus nodes left while the residual
    // climbed to 0.38 and stalled).
    const Communicator& comm = hs_.communicator();
    bool restart = entered;
    if (comm.sum(double(left)) > kBulkExit * comm.sum(double(on_.size()))) restart = true;
    restart = comm.any(restart);
    // Few changed nodes: direct summation (~n^2 per node) beats a convolution (~4 n^2 log n)
    // below HalfSpace::sparse_limit(), measured in tools/bench/convolution. The count is the
    // grid's: on a distributed grid every rank takes the same branch of the collective product.
    if (comm.sum(double(idx_.size())) <= double(hs_.sparse_limit())) {
      hs_.normal_add_sparse(idx_, val_, s_.u_);
    } else {
      hs_.normal(p_, s_.u_);
      pending_tau_ = 0.0;
    }
    if (force_control_) {
      // p is zero off S and the entered nodes.
      double force = 0.0;
      for (const Eigen::Index k : on_) force += p_(k);
      if (tau > 0.0)
        for (const Eigen::Index k : pen_) force += p_(k);
      const double scale = target_ / (comm.sum(force) * hs_.grid().cell_area());
      for (const Eigen::Index k : on_) p_(k) *= scale;
      if (tau > 0.0)
        for (const Eigen::Index k : pen_) p_(k) *= scale;
      pending_scale_ = scale;
    }
    return restart;
  }

  NormalSolver& s_;
  HalfSpace& hs_;
  const bool force_control_;
  const double target_;
  Field& p_;
  bool pre_ = false, cold_, forced_ = false;
  double residual_ = 0.0, delta_ = 0.0;
  double gg_ = 0.0, off_ = 0.0;  // g . g on S, squared penetration off S (this rank)
  // The step u still owes: u <- (u - pending_tau_ r) pending_scale_, done in the gap pass.
  bool pending_ = false;
  double pending_tau_ = 0.0, pending_scale_ = 1.0;
  std::vector<Eigen::Index> on_;      // S = {p > 0} at the last residual, in grid order
  std::vector<Eigen::Index> pen_;     // nodes off S with a negative gap at the last residual
  std::vector<Eigen::Index> t_on_;    // where t is nonzero (the S of the last step)
  std::vector<double> next_t_;        // t's new values on S
  Eigen::ArrayXXd S_;                 // contact set as a mask, for the preconditioner
  const Field* direction_ = nullptr;  // raw direction of this iteration: g_ or z_
  std::vector<std::int64_t> idx_;
  std::vector<double> val_;
};

NormalResult NormalSolver::solve(const Field& z, bool force_control, double target, Field& p) {
  const Grid& grid = hs_.grid();
  const auto conv0 = hs_.convolutions();
  h0_ = hs_.communicator().max(z.size() ? z.maxCoeff() : -HUGE_VAL) - z;
  NormalResult res;
  if (target <= 0.0) {  // no load: nothing touches (delta = 0 at first touch)
    p = hs_.local_zeros();
    u_ = hs_.local_zeros();
    res.converged = true;
    return res;
  }
  // Without a warm start the first guess is the cold one already.
  const bool warm = is_warm(hs_, p);
  initial_guess(force_control, target, p);
  hs_.normal(p, u_);
  t_ = hs_.local_zeros();
  Iteration iteration(*this, force_control, target, p, warm);
  cg::Rules rules;
  rules.tolerance = opt_.tolerance;
  rules.last_pass = opt_.max_iterations;
  // u is updated on the whole grid every iteration: the verifying product would only confirm
  // a residual that the updates' round-off cannot move (one product a solve). displacement()
  // is then K p to that round-off.
  rules.verify = !(hs_.min_tolerance() == 0.0 && opt_.tolerance >= cg::kUnverifiedTolerance);
  const cg::Outcome out = cg::run(iteration, rules);
  iteration.settle();
  res.iterations = out.iterations;
  res.residual = out.residual;
  res.converged = out.converged;
  res.force = total(hs_, p) * grid.cell_area();
  res.indentation = iteration.indentation();
  res.convolutions = int(hs_.convolutions() - conv0);
  if (!res.converged) {
    std::ostringstream msg;
    msg << "normal solver did not converge: residual " << res.residual << " > tolerance "
        << opt_.tolerance << " after " << res.iterations << " iterations";
    throw SolverError(msg.str());
  }
  return res;
}

}  // namespace fretbem
