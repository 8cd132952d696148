// The Polonsky–Keer normal solve on a grid distributed over MPI ranks against the serial solve
// of the same problem: a Hertz sphere (force and indentation control) and a periodic rough
// surface (force control), plain and preconditioned. The two solves differ only in the order
// of the reductions' sums (one sum per rank, then over the ranks), a relative 1e-16 per
// product; both are run to a residual of 1e-13, so that their pressures agree to ~1e-12 and
// the 1e-10 asked of the distributed solve is not a statement about the stopping rule.
#include <gtest/gtest.h>

#include <random>

#include "fretbem/contact/normal_solver.hpp"
#include "fretbem/elastic/half_space.hpp"
#include "mpi_test_util.hpp"

using namespace fretbem;

namespace {

constexpr double kTolerance = 1e-10;

struct Case {
  Grid grid;
  Field z;  // indenter heights (m), peaks positive
};

// Sphere R = 10 mm on a 1 mm free grid: Hertz radius 0.32 mm (~L/3) at 1 kN or 10 um.
Case sphere(int n) {
  Case c{Grid::square(n, 1e-3), Field(n, n)};
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = c.grid.x(i), y = c.grid.y(j);
      c.z(i, j) = -(x * x + y * y) / (2 * 10e-3);
    }
  return c;
}

// Random periodic heights, rms ~ 0.3 um on a 1 mm grid (a rough contact of many islands).
Case rough(int n) {
  Case c{Grid::square(n, 1e-3, true), Field(n, n)};
  std::mt19937 rng(5);
  std::normal_distribution<double> g(0.0, 0.3e-6);
  for (Eigen::Index k = 0; k < c.z.size(); ++k) c.z(k) = g(rng);
  return c;
}

// Solves serially and distributed; the pressure slabs, force and indentation must agree.
void expect_same_solution(const Case& c, bool force_control, double target, Precondition pre) {
  const Communicator& world = world_communicator();
  const Material m{Body{210e9, 0.3}, std::nullopt, 0.3};
  HalfSpace hs(c.grid, m, Coupling::analogy);
  HalfSpace hd(c.grid, m, Coupling::analogy, {}, world);
  const NormalOptions opt{1e-13, 4000, pre};
  NormalSolver ss(hs, opt), sd(hd, opt);
  Field ps, pd;
  const Field zd = c.z.middleCols(hd.first_row(), hd.local_rows());
  const NormalResult rs =
      force_control ? ss.solve_force(c.z, target, ps) : ss.solve_indentation(c.z, target, ps);
  const NormalResult rd =
      force_control ? sd.solve_force(zd, target, pd) : sd.solve_indentation(zd, target, pd);
  const Field mine = ps.middleCols(hd.first_row(), hd.local_rows());
  const double diff = world.max(pd.size() ? (pd - mine).abs().maxCoeff() : 0.0);
  EXPECT_LT(diff / ps.maxCoeff(), kTolerance);
  EXPECT_NEAR(rd.force, rs.force, kTolerance * rs.force);
  EXPECT_NEAR(rd.indentation, rs.indentation, kTolerance * std::abs(rs.indentation));
  EXPECT_TRUE(rd.converged);
  // Warm start from the solution: both solves confirm it and stay on it.
  const NormalResult ws = ss.solve_force(c.z, rs.force, ps);
  const NormalResult wd = sd.solve_force(zd, rs.force, pd);
  EXPECT_EQ(wd.iterations, ws.iterations);
}

}  // namespace

TEST(NormalSolverMpi, HertzForceControlEqualsSerial) {
  if (!mpi_test::on_ranks()) return mpi_test::run_on_ranks(2);
  expect_same_solution(sphere(63), true, 1e3, Precondition::off);
}

TEST(NormalSolverMpi, HertzIndentationControlEqualsSerial) {
  if (!mpi_test::on_ranks()) return mpi_test::run_on_ranks(2);
  expect_same_solution(sphere(63), false, 1e-5, Precondition::off);
}

TEST(NormalSolverMpi, PreconditionedHertzEqualsSerial) {
  if (!mpi_test::on_ranks()) return mpi_test::run_on_ranks(2);
  expect_same_solution(sphere(64), true, 1e3, Precondition::on);
}

TEST(NormalSolverMpi, PeriodicRoughForceControlEqualsSerial) {
  if (!mpi_test::on_ranks()) return mpi_test::run_on_ranks(2);
  expect_same_solution(rough(64), true, 200.0, Precondition::off);
}
