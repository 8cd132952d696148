// WearPreconditioner (the frozen-slip Newton matrix of the implicit wear integrator)
// against its definition: P x = b checked by applying P with dense linear algebra.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "fretbem/wear/preconditioner.hpp"

using namespace fretbem;

namespace {

// Applies P = I - gamma J, J v = d (.) q(v), with q(v) the pressure response to removing v on
// the contact set A: C q = dd 1 - v on A, sum q = 0 under force control (dd = 0 otherwise),
// solved densely — the influence matrix assembled column by column from unit pressures and the
// (bordered) system solved by Eigen's LU, for c0 q (m) with C / c0 (c0 the self-compliance) so
// that every entry is O(1).
Field apply_newton_matrix(HalfSpace& hs, const Field& mask, const Field& d, const Field& v,
                          double gamma, bool force_control) {
  const Grid& g = hs.grid();
  std::vector<int> A;
  for (int k = 0; k < int(g.size()); ++k)
    if (mask.data()[k] > 0) A.push_back(k);
  const int m = int(A.size()), nb = force_control ? m + 1 : m;
  const double c0 = hs.normal_self();
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(nb, nb);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(nb);
  Field e = g.zeros(), u;
  for (int j = 0; j < m; ++j) {
    e.data()[A[j]] = 1.0;
    hs.normal(e, u);
    e.data()[A[j]] = 0.0;
    for (int i = 0; i < m; ++i) M(i, j) = u.data()[A[i]] / c0;
    rhs(j) = -v.data()[A[j]];
    if (force_control) M(j, m) = -1.0, M(m, j) = 1.0;
  }
  const Eigen::VectorXd q = M.fullPivLu().solve(rhs) / c0;
  Field out = v;
  for (int i = 0; i < m; ++i) out.data()[A[i]] -= gamma * d.data()[A[i]] * q(i);
  return out;
}

}  // namespace

TEST(WearPreconditioner, SolvesTheFrozenSlipNewtonMatrixExactly) {
  const Grid g = Grid::square(12, 1e-4);
  Material mat;
  mat.body1 = {210e9, 0.3};
  HalfSpace hs(g, mat, Coupling::analogy);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  // A disc of contact; wear per cycle k p S (k = 5e-14 1/Pa) with S up to 0.2 um in an outer
  // annulus, so that gamma d / C(0,0) spans 0 ... ~10^2 for gamma = 0 ... 1e5 cycles.
  Field p = g.zeros(), w = g.zeros(), b(g.nx, g.ny);
  for (int i = 0; i < g.nx; ++i)
    for (int j = 0; j < g.ny; ++j) {
      const double r2 = (g.x(i) * g.x(i) + g.y(j) * g.y(j)) / (4e-5 * 4e-5);
      if (r2 < 1.0) p(i, j) = 1e9 * std::sqrt(1.0 - r2);
      if (r2 > 0.4 && r2 < 1.0) w(i, j) = 5e-14 * p(i, j) * 2e-7 * r2;
      b(i, j) = uni(rng) - 0.5;
    }
  for (const bool force_control : {true, false})
    for (const double gamma : {0.0, 1e3, 1e5}) {
      WearPreconditioner pre(hs, force_control, 1e-12);
      pre.setup(p, w);
      Field x;
      pre.solve(b, gamma, x);
      const Field d = (w / p.max(1e-300)) * (p > 0).cast<double>();
      const Field Px = apply_newton_matrix(hs, (p > 0).cast<double>(), d, x, gamma, force_control);
      EXPECT_LE(std::sqrt((Px - b).square().sum()), 1e-9 * std::sqrt(b.square().sum()))
          << "force control " << force_control << ", gamma " << gamma;
    }
}
