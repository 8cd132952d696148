// WearPreconditioner (the frozen-slip Newton matrix of the implicit wear integrator)
// against its definition: P x = b checked by applying P with dense linear algebra.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "fretbem/wear/preconditioner.hpp"
#include "support/worn_disc.hpp"

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

// The worn disc of support/worn_disc.hpp on a 12 x 12 grid of steel.
struct Disc12 {
  Grid g = Grid::square(12, 1e-4);
  Material mat = steel();
  HalfSpace hs{g, mat, Coupling::analogy};
  fretbem_test::WornDisc disc = fretbem_test::worn_disc(g);
  static Material steel() {
    Material m;
    m.body1 = {210e9, 0.3};
    return m;
  }
};

}  // namespace

TEST(WearPreconditioner, SolvesTheFrozenSlipNewtonMatrixExactly) {
  Disc12 disc;
  HalfSpace& hs = disc.hs;
  const Field &p = disc.disc.pressure, &w = disc.disc.wear_per_cycle, &b = disc.disc.rhs;
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

// Asked for a residual of 1e-2 |b| (what ARKODE's linear tolerance is on the implicit wear
// steps, 3e-3 to 1e-2 of |b| measured on rough_fretting_wear.ini), the inner CG stops there:
// x is within that residual of the dense solution (its error gamma D (C_A + gamma D)^-1 r has
// eigenvalues in [0, 1)), in fewer products than the solve to 1e-12.
TEST(WearPreconditioner, StopsAtTheResidualAskedFor) {
  Disc12 disc;
  HalfSpace& hs = disc.hs;
  const Field &p = disc.disc.pressure, &w = disc.disc.wear_per_cycle, &b = disc.disc.rhs;
  const double allowed = 1e-2 * std::sqrt(b.square().sum());
  for (const bool force_control : {true, false})
    for (const double gamma : {1e3, 1e5}) {
      WearPreconditioner tight(hs, force_control, 1e-12), loose(hs, force_control, 1e-12);
      tight.setup(p, w);
      loose.setup(p, w);
      Field exact, x;
      tight.solve(b, gamma, exact);
      loose.solve(b, gamma, x, allowed);
      EXPECT_LE(std::sqrt((x - exact).square().sum()), allowed)
          << "force control " << force_control << ", gamma " << gamma;
      EXPECT_LT(loose.iterations(), tight.iterations())
          << "force control " << force_control << ", gamma " << gamma;
    }
}
