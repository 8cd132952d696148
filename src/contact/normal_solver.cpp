#include "fretbem/contact/normal_solver.hpp"

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
class NormalSolver::Iteration {
 public:
  Iteration(NormalSolver& s, bool force_control, double target, Field& p, bool warm)
      : s_(s), hs_(s.hs_), force_control_(force_control), target_(target), p_(p), cold_(!warm) {
    const PreconditionDecision decision(s.opt_.precondition);
    const bool by_set = s.opt_.precondition_by_set && warm && !hs_.communicator().distributed();
    pre_ = by_set ? decision.for_set((p_ > 0.0).cast<double>()) : decision.for_grid(hs_.grid());
  }

  // Gap on the current contact set S = {p > 0}; under force control delta is the multiplier
  // that makes the mean gap on S vanish.
  double residual() {
    residual_ = s_.gap_residual(force_control_, target_, p_, &delta_);
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
  void refresh() { hs_.normal(p_, s_.u_); }
  bool exhausted(int it, const cg::Watch&) const { return it == s_.opt_.max_iterations; }

  // G = g . z on S, z the gap itself (Polonsky–Keer) or the preconditioned z = S K^-1 (S g).
  double gradient_product() {
    S_ = (p_ > 0.0).cast<double>();  // evaluated now: p changes in the step
    direction_ =
        forced_ || pre_ ? &preconditioned_direction(hs_, S_, s_.g_, force_control_, s_.z_) : &s_.g_;
    return total(hs_, S_ * s_.g_ * *direction_);
  }

  cg::Step step(double beta) {
    Field &t = s_.t_, &r = s_.r_;
    t = S_ * (*direction_ + beta * t);
    hs_.normal(t, r);
    double rbar = 0.0;
    if (force_control_) rbar = total(hs_, S_ * r) / std::max(1.0, total(hs_, S_));
    const double denom = total(hs_, S_ * (r - rbar) * t);
    if (!(denom > 0.0)) {
      // No descent on S. At round-off level that is the end; far from it, the warm start's
      // contact set was wrong in a way the iteration cannot leave (e.g. one node, where the
      // mean-free gap on S vanishes): restart once from the cold guess.
      if (cold_ || residual_ < 1e3 * s_.opt_.tolerance) return {cg::Next::stop};
      cold_start();
      return {cg::Next::restart};
    }
    const double tau = total(hs_, S_ * s_.g_ * t) / denom;
    p_ -= tau * t;
    s_.u_ -= tau * r;
    return {cg::Next::proceed, project(tau)};
  }

  double indentation() const { return delta_; }

 private:
  void cold_start() {
    cold_ = true;
    p_ = Field();
    s_.initial_guess(force_control_, target_, p_);
    hs_.normal(p_, s_.u_);
  }

  // After p <- p - tau t, u <- u - tau K t: projection p >= 0 and re-entry of penetrating
  // nodes, whose (sparse) displacement change is added separately; under force control the
  // pressure is rescaled to the force. Returns whether conjugacy restarts.
  bool project(double tau) {
    const Field& g = s_.g_;
    idx_.clear(), val_.clear();
    bool restart = false;
    std::int64_t left = 0;
    for (Eigen::Index k = 0; k < p_.size(); ++k) {
      double e = 0.0;
      if (S_(k) > 0 && p_(k) < 0.0) {
        e = -p_(k);
        ++left;
      } else if (S_(k) == 0 && g(k) < 0.0 && tau > 0.0) {
        e = -tau * g(k);
        restart = true;
      }
      if (e != 0.0) p_(k) += e, idx_.push_back(k), val_.push_back(e);
    }
    // Nodes leaving contact in bulk change S, and with it the problem CG was conjugating on
    // (PK restart only on re-entry; measured: ~3700 annulus nodes left while the residual
    // climbed to 0.38 and stalled).
    const Communicator& comm = hs_.communicator();
    if (comm.sum(double(left)) > kBulkExit * total(hs_, S_)) restart = true;
    restart = comm.any(restart);
    // Few changed nodes: direct summation (~n^2 per node) beats a convolution (~4 n^2 log n)
    // below HalfSpace::sparse_limit(), measured in tools/bench/convolution. The count is the
    // grid's: on a distributed grid every rank takes the same branch of the collective product.
    if (comm.sum(double(idx_.size())) <= double(hs_.sparse_limit()))
      hs_.normal_add_sparse(idx_, val_, s_.u_);
    else
      hs_.normal(p_, s_.u_);
    if (force_control_) {
      const double scale = target_ / (total(hs_, p_) * hs_.grid().cell_area());
      p_ *= scale;
      s_.u_ *= scale;
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
  Eigen::ArrayXXd S_;                 // contact set of this iteration (1 on S)
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
  const cg::Outcome out = cg::run(iteration, rules);
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

// Relative KKT residual: rms gap on S and rms penetration off S, over the rms displacement on S.
double NormalSolver::gap_residual(bool force_control, double delta, const Field& p,
                                  double* delta_out) {
  const auto S = (p > 0.0);
  const double count = hs_.communicator().sum(double(S.count()));
  const auto n = std::max<double>(1, count);
  Field& g = g_;
  g = u_ + h0_;
  if (force_control) delta = total(hs_, S.cast<double>() * g) / n;
  g -= delta;
  *delta_out = delta;
  const double on = total(hs_, S.cast<double>() * g * g);
  const double off = total(hs_, S.select(0.0, g.min(0.0)).square());
  // Scale: the rms displacement on S, or the rms height variation over S when that is larger.
  // The second matters on periodic grids, where a uniform pressure displaces nothing (the
  // mean mode has zero compliance): the displacement alone would call full contact converged.
  const auto Sd = S.cast<double>();
  const double h0bar = total(hs_, Sd * h0_) / n;
  const double scale = std::max(std::sqrt(total(hs_, Sd * u_ * u_) / n),
                                std::sqrt(total(hs_, Sd * (h0_ - h0bar).square()) / n));
  if (!(scale > 0.0)) return count == 0 ? 1.0 : 0.0;
  return std::sqrt((on + off) / n) / scale;
}

}  // namespace fretbem
