#include "fretbem/contact/tangential_solver.hpp"

#include <cmath>
#include <limits>
#include <type_traits>

#include "tangential_detail.hpp"

namespace fretbem {

using namespace tangential_detail;

double coulomb_residual(const Grid& grid, const TangentialIncrement& inc, const VecField& tau,
                        const VecField& u, double scale, Eigen::VectorXd& dU, VecField& s) {
  NodeSets sets(*inc.bound);
  double stick_slip2 = 0.0;
  const double res = residual(sets, inc, tau, u, scale, grid, dU, stick_slip2);
  s.resize(tau.size());
  for (std::size_t c = 0; c < tau.size(); ++c) s[c] = dU(c) - (u[c] - (*inc.u0)[c]);
  return res;
}

ProjectedCgSolver::ProjectedCgSolver(TangentialOperator& op, TangentialOptions opt)
    : op_(op), opt_(opt), cache_(std::make_unique<ScaleCache>()) {
  op_.half_space().require_tolerance(opt_.tolerance, "tangential solver");
}

ProjectedCgSolver::~ProjectedCgSolver() = default;

std::int64_t largest_contact_patch(const Field& bound) {
  const Eigen::Index nx = bound.rows(), ny = bound.cols();
  std::vector<std::uint8_t> seen(std::size_t(bound.size()), 0);
  std::vector<Eigen::Index> stack;
  std::int64_t largest = 0;
  for (Eigen::Index k0 = 0; k0 < bound.size(); ++k0) {
    if (!(bound(k0) > 0.0) || seen[k0]) continue;
    std::int64_t size = 0;
    stack.assign(1, k0), seen[k0] = 1;
    while (!stack.empty()) {  // flood fill over the 4-neighbours
      const Eigen::Index k = stack.back(), i = k % nx, j = k / nx;
      stack.pop_back(), ++size;
      const Eigen::Index next[4] = {i > 0 ? k - 1 : -1, i + 1 < nx ? k + 1 : -1,
                                    j > 0 ? k - nx : -1, j + 1 < ny ? k + nx : -1};
      for (const Eigen::Index m : next)
        if (m >= 0 && bound(m) > 0.0 && !seen[m]) seen[m] = 1, stack.push_back(m);
    }
    largest = std::max(largest, size);
  }
  return largest;
}

// Automatic: on when the largest contact patch is wide. Plain CG on the stick set needs
// iterations growing with the patch's diameter (sqrt of the condition number), the Fourier
// preconditioner removes that growth at the price of a second transform pair per iteration.
// Measured (bench_tangential, CPU time PCG / plain): Hertz contact (one patch of 3252, 12900,
// 51540 nodes at n = 128, 256, 512) 0.7, 0.5-0.6, 0.4; rough contact with largest patches of
// 174-614 nodes 0.97-1.25, of 2407 nodes 0.74-0.83 (docs/performance.md).
bool ProjectedCgSolver::preconditioned(const Field& bound) const {
  if (opt_.precondition != Precondition::automatic) return opt_.precondition == Precondition::on;
  return largest_contact_patch(bound) >= kPatchNodes;
}

// The flood fill is a pass over the grid per increment (4 % of a full-sliding step of
// rough_monotone.ini, perf); fewer contact nodes than kPatchNodes cannot form such a patch.
bool ProjectedCgSolver::preconditioned(const Field& bound,
                                       const std::vector<Eigen::Index>& contact) {
  if (opt_.precondition != Precondition::automatic) return opt_.precondition == Precondition::on;
  if (std::int64_t(contact.size()) < kPatchNodes) return false;
  if (contact != patch_key_) {
    patch_key_ = contact;
    patch_pre_ = largest_contact_patch(bound) >= kPatchNodes;
  }
  return patch_pre_;
}

TangentialResult ProjectedCgSolver::solve(const TangentialIncrement& inc, VecField& tau,
                                          VecField& u) {
  if (op_.components() == 1) return solve_components<1>(inc, tau, u);
  return solve_components<2>(inc, tau, u);
}

// Residual growth by this factor within one iteration restarts conjugacy. CG on a fixed set
// does not keep the residual monotone, but a doubling in one step signals a change from
// outside its recurrence (u recomputed, a force correction, nodes released or put back).
constexpr double kResidualJump = 2.0;
constexpr int kStagnation = 1000;

template <int NC>
TangentialResult ProjectedCgSolver::solve_components(const TangentialIncrement& inc, VecField& tau,
                                                     VecField& u) {
  using Vec = Eigen::Matrix<double, NC, 1>;
  Workspace w(op_, inc, opt_, *cache_);
  w.start(tau, u);
  const std::vector<Eigen::Index>& contact = w.sets.contact;
  const std::vector<std::uint8_t>& stick = w.sets.stick;
  const bool pre = preconditioned(*inc.bound, contact);
  // Off contact the direction stays zero: only contact entries are ever written.
  d_ = op_.zeros();
  if (pre) r_ = op_.zeros(), z_.resize(NC);
  auto slip = [&](const Vec& dU, Eigen::Index k) {
    Vec s;
    for (int c = 0; c < NC; ++c) s(c) = dU(c) - (u[c](k) - (*inc.u0)[c](k));
    return s;
  };
  // A start imaged by one product needs no verifying product: u = C tau has not drifted yet.
  bool restart = true, verified = w.exact;
  double g_old = 1.0, last_residual = std::numeric_limits<double>::infinity();
  double best = last_residual;
  int best_it = 0;
  for (int it = 0;; ++it) {
    w.result.iterations = it;
    double G = 0.0;
    w.result.residual = w.residual(tau, u, G);  // classifies the stick set S
    // Conjugacy holds only for the residual it was built on: a residual that jumps (u
    // recomputed, a force correction, nodes released) starts a new Krylov space. Continuing
    // with beta = G / g_old ~ 1e10 after such a jump made the iteration crawl (issue 12).
    if (w.result.residual > kResidualJump * last_residual) restart = true;
    last_residual = w.result.residual;
    if (w.result.residual < best) best = w.result.residual, best_it = it;
    if (w.result.residual <= opt_.tolerance) {
      if (verified) {
        w.result.converged = true;
        break;
      }
      op_.apply(tau, u);  // drop round-off of the incremental updates, then check again
      verified = true, restart = true;
      continue;
    }
    verified = false;
    // No new best residual for kStagnation iterations: hand over to the fallbacks now rather
    // than after max_iterations (measured: a diverging force-controlled increment cycled with
    // period ~1500 iterations between residuals 0.39 and 0.62).
    if (it >= opt_.max_iterations || it - best_it > kStagnation) break;
    // CG on the stick set. The QP's gradient is -s; under force control s has zero mean on
    // the stick set (dU is that mean), so the directions keep the total force.
    const Vec dU = w.result.shift;
    Vec zbar = Vec::Zero();
    if (pre && w.sets.nstick > 0) {
      // Preconditioned direction z = S K^-1 (S s): the Fourier inverse of the kernel, as the
      // normal solver's PCG (Vollebregt, J. Comput. Phys. 257, 2014). The analogy operator is
      // (E*/G*) K_z and CG is blind to the constant factor; for Cerruti K_z^-1 per component
      // is a spectrally equivalent SPD approximation. Under force control z is made mean-free
      // on S so that the directions keep the force (s . z is unchanged: s is mean-free on S).
      for (std::size_t j = 0; j < contact.size(); ++j) {
        const Vec s = stick[j] ? slip(dU, contact[j]) : Vec::Zero();
        for (int c = 0; c < NC; ++c) r_[c](contact[j]) = s(c);
      }
      for (int c = 0; c < NC; ++c) op_.half_space().normal_inverse(r_[c], z_[c]);
      if (inc.control == TangentialControl::force) {
        for (std::size_t j = 0; j < contact.size(); ++j)
          if (stick[j])
            for (int c = 0; c < NC; ++c) zbar(c) += z_[c](contact[j]);
        zbar /= double(w.sets.nstick);
      }
      G = 0.0;
      for (std::size_t j = 0; j < contact.size(); ++j) {
        if (!stick[j]) continue;
        const Eigen::Index k = contact[j];
        for (int c = 0; c < NC; ++c) G += (r_[c](k)) * (z_[c](k) - zbar(c));
      }
    }
    const double beta = restart ? 0.0 : G / g_old;
    g_old = G;
    double num = 0.0;
    for (std::size_t j = 0; j < contact.size(); ++j) {
      const Eigen::Index k = contact[j];
      if (!stick[j]) {
        for (int c = 0; c < NC; ++c) d_[c](k) = 0.0;
        continue;
      }
      const Vec s = slip(dU, k);
      for (int c = 0; c < NC; ++c) {
        d_[c](k) = (pre ? z_[c](k) - zbar(c) : s(c)) + beta * d_[c](k);
        num += s(c) * d_[c](k);
      }
    }
    double alpha = 0.0;
    if (G > 0.0) {
      op_.apply(d_, q_);
      // d . C d on S, with q made mean-free on S under force control (the multiplier dU
      // absorbs the mean).
      Vec qd = Vec::Zero(), qsum = Vec::Zero(), dsum = Vec::Zero();
      for (std::size_t j = 0; j < contact.size(); ++j) {
        if (!stick[j]) continue;
        const Eigen::Index k = contact[j];
        for (int c = 0; c < NC; ++c)
          qd(c) += q_[c](k) * d_[c](k), qsum(c) += q_[c](k), dsum(c) += d_[c](k);
      }
      double den = qd.sum();
      if (inc.control == TangentialControl::force)
        den -= qsum.dot(dsum) / double(std::max<std::int64_t>(1, w.sets.nstick));
      if (den > 0.0) alpha = num / den;
    }
    restart = w.step_and_project(alpha, d_, q_, tau, u) || !(alpha > 0.0);
  }
  return w.finish(tau, "projected-CG");
}

}  // namespace fretbem
