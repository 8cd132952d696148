#include "fretbem/contact/normal_solver.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <vector>

#include "fretbem/core/errors.hpp"

namespace fretbem {

namespace {
// Fraction of the contact set whose leaving in one iteration restarts conjugacy.
constexpr double kBulkExit = 0.01;
// Cold start (once) when the residual exceeds the best so far by this factor, or has not
// improved on it for this many iterations.
constexpr double kGrowth = 100.0;
constexpr int kStagnation = 200;

// Whether solver.precondition asks for the preconditioned direction.
bool preconditioned(const NormalOptions& opt, const Grid& g) {
  return opt.precondition == Precondition::on ||
         (opt.precondition == Precondition::automatic && g.size() >= 256 * 256);
}

// z = S K^-1 (S g), mean-free on S under force control so that directions keep the force (g is
// mean-free on S there, so g . z is unchanged by the shift).
const Field& preconditioned_direction(HalfSpace& hs, const Eigen::ArrayXXd& S, const Field& g,
                                      bool force_control, Field& z) {
  hs.normal_inverse(S * g, z);
  z *= S;
  if (force_control) z -= S * ((S * z).sum() / std::max(1.0, S.sum()));
  return z;
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
  const bool warm = p.rows() == g.nx && p.cols() == g.ny && (p > 0).any();
  if (force_control) {
    if (warm) {
      p = p.max(0.0);
      p *= target / (p.sum() * g.cell_area());
    } else {
      p = Field::Constant(g.nx, g.ny, target / (g.size() * g.cell_area()));
    }
  } else if (!warm) {
    p = ((target - h0_) / hs_.normal_self()).max(0.0);
  }
}

NormalResult NormalSolver::solve(const Field& z, bool force_control, double target, Field& p) {
  const Grid& grid = hs_.grid();
  const auto conv0 = hs_.convolutions();
  h0_ = z.maxCoeff() - z;
  NormalResult res;
  if (target <= 0.0) {  // no load: nothing touches (delta = 0 at first touch)
    p = grid.zeros();
    u_ = grid.zeros();
    res.converged = true;
    return res;
  }
  // Without a warm start the first guess is the cold one already.
  const bool warm = p.rows() == grid.nx && p.cols() == grid.ny && (p > 0).any();
  initial_guess(force_control, target, p);
  hs_.normal(p, u_);
  const double area = grid.cell_area();
  double g_old = 1.0, delta = force_control ? 0.0 : target;
  bool restart = true, verified = false, cold = !warm, forced = false;
  std::vector<std::int64_t> idx;
  std::vector<double> val;
  t_ = grid.zeros();
  // Stagnation and growth watch: the best residual so far and the iteration that reached it.
  double best = std::numeric_limits<double>::infinity();
  int best_it = 0;
  auto cold_start = [&] {
    cold = true, restart = true;
    best = std::numeric_limits<double>::infinity();
    p = Field();
    initial_guess(force_control, target, p);
    hs_.normal(p, u_);
  };
  for (int it = 0; it <= opt_.max_iterations; ++it) {
    // Gap on the current contact set S = {p > 0}; under force control delta is the multiplier
    // that makes the mean gap on S vanish.
    res.residual = gap_residual(force_control, target, p, &delta);
    res.iterations = it;
    if (res.residual < best) best = res.residual, best_it = it;
    // A warm start far from the solution (thousands of nodes to leave a worn annulus, issue
    // 12) can make the iteration climb or stall; the cold start does not depend on it. From
    // the cold start, plain Polonsky–Keer can cycle on a worn conforming annulus (measured,
    // issue 12: n = 32, Q = 0.9 mu P, contact sets of 468 -> 268 -> 132 -> 468 nodes, residual
    // 0.11 -> 0.023 -> 0.016, period 3, for 5000 iterations); the preconditioned direction
    // S K^-1 S g converged there in 17 iterations: it is the last resort.
    const bool stalled = res.residual > kGrowth * best || it - best_it > kStagnation;
    if (stalled && (!cold || !(forced || preconditioned(opt_, grid)))) {
      forced = cold;
      cold_start();
      continue;
    }
    if (res.residual <= opt_.tolerance) {
      if (verified) {
        res.converged = true;
        break;
      }
      hs_.normal(p, u_);  // drop accumulated round-off of the incremental updates, then re-check
      verified = true;
      continue;
    }
    verified = false;
    if (it == opt_.max_iterations) break;
    const Eigen::ArrayXXd S = (p > 0.0).cast<double>();  // evaluated now: p changes below
    const Field& z = forced ? preconditioned_direction(hs_, S, g_, force_control, z_)
                            : precondition(S, force_control);
    const double G = (S * g_ * z).sum();
    t_ = S * (z + (restart ? 0.0 : G / g_old) * t_);
    g_old = G;
    hs_.normal(t_, r_);
    double rbar = 0.0;
    if (force_control) rbar = (S * r_).sum() / std::max(1.0, S.sum());
    const double denom = (S * (r_ - rbar) * t_).sum();
    if (!(denom > 0.0)) {
      // No descent on S. At round-off level that is the end; far from it, the warm start's
      // contact set was wrong in a way the iteration cannot leave (e.g. one node, where the
      // mean-free gap on S vanishes): restart once from the cold guess.
      if (cold || res.residual < 1e3 * opt_.tolerance) break;
      cold_start();
      continue;
    }
    const double tau = (S * g_ * t_).sum() / denom;
    // p <- p - tau t, u <- u - tau K t; then projection p >= 0 and re-entry of penetrating
    // nodes, whose (sparse) displacement change is added separately.
    p -= tau * t_;
    u_ -= tau * r_;
    idx.clear(), val.clear();
    restart = false;
    std::int64_t left = 0;
    for (Eigen::Index k = 0; k < p.size(); ++k) {
      double e = 0.0;
      if (S(k) > 0 && p(k) < 0.0) {
        e = -p(k);
        ++left;
      } else if (S(k) == 0 && g_(k) < 0.0 && tau > 0.0) {
        e = -tau * g_(k);
        restart = true;
      }
      if (e != 0.0) p(k) += e, idx.push_back(k), val.push_back(e);
    }
    // Nodes leaving contact in bulk change S, and with it the problem CG was conjugating on
    // (PK restart only on re-entry; measured, issue 12: ~3700 annulus nodes left while the
    // residual climbed to 0.38 and stalled).
    if (double(left) > kBulkExit * S.sum()) restart = true;
    // Few changed nodes: direct summation (~n^2 per node) beats a convolution (~4 n^2 log n)
    // below HalfSpace::sparse_limit(), measured in tools/bench/convolution.
    if (idx.size() <= hs_.sparse_limit())
      hs_.normal_add_sparse(idx, val, u_);
    else
      hs_.normal(p, u_);
    if (force_control) {
      const double scale = target / (p.sum() * area);
      p *= scale;
      u_ *= scale;
    }
  }
  res.force = p.sum() * area;
  res.indentation = delta;
  res.convolutions = int(hs_.convolutions() - conv0);
  if (!res.converged) {
    std::ostringstream msg;
    msg << "normal solver did not converge: residual " << res.residual << " > tolerance "
        << opt_.tolerance << " after " << res.iterations << " iterations";
    throw SolverError(msg.str());
  }
  return res;
}

// The search direction's raw material: the gap g itself (Polonsky–Keer) or, preconditioned,
// z = S K^-1 (S g) (preconditioned_direction).
const Field& NormalSolver::precondition(const Eigen::ArrayXXd& S, bool force_control) {
  if (!preconditioned(opt_, hs_.grid())) return g_;
  return preconditioned_direction(hs_, S, g_, force_control, z_);
}

// Relative KKT residual: rms gap on S and rms penetration off S, over the rms displacement on S.
double NormalSolver::gap_residual(bool force_control, double delta, const Field& p,
                                  double* delta_out) {
  const auto S = (p > 0.0);
  const auto n = std::max<double>(1, S.count());
  Field& g = g_;
  g = u_ + h0_;
  if (force_control) delta = (S.cast<double>() * g).sum() / n;
  g -= delta;
  *delta_out = delta;
  const double on = (S.cast<double>() * g * g).sum();
  const double off = (S.select(0.0, g.min(0.0))).square().sum();
  // Scale: the rms displacement on S, or the rms height variation over S when that is larger.
  // The second matters on periodic grids, where a uniform pressure displaces nothing (the
  // mean mode has zero compliance): the displacement alone would call full contact converged.
  const auto Sd = S.cast<double>();
  const double h0bar = (Sd * h0_).sum() / n;
  const double scale = std::max(std::sqrt((Sd * u_ * u_).sum() / n),
                                std::sqrt((Sd * (h0_ - h0bar).square()).sum() / n));
  if (!(scale > 0.0)) return S.count() == 0 ? 1.0 : 0.0;
  return std::sqrt((on + off) / n) / scale;
}

}  // namespace fretbem
