// The tangential (partial-slip) and stiffness solves on a grid distributed over MPI ranks
// against the serial solves of the same increments: a Cattaneo ramp and a Mindlin reversal of
// a Hertz contact under force and displacement control, projected CG (plain and
// preconditioned) and the partition method, the analogy (one component) and Cerruti (two
// components), on two ranks and on three (uneven slabs); after every increment the
// differential stiffness k_x of its stick set. Both sides share one serial pressure, start from the
// same state and solve every increment to 1e-13, so their tractions agree to ~1e-12 (the reductions
// only change the order of the sums, a relative 1e-16 per product) and the 1e-10 asked of the
// distributed solve is not a statement about the stopping rule.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "fretbem/contact/normal_solver.hpp"
#include "fretbem/contact/stiffness.hpp"
#include "fretbem/contact/tangential_solver.hpp"
#include "fretbem/elastic/half_space.hpp"
#include "mpi_test_util.hpp"

using namespace fretbem;

namespace {

constexpr double kTolerance = 1e-10;
constexpr double kMu = 0.3;

enum class Algorithm { projected, partition };

struct Load {
  TangentialControl control;
  Eigen::VectorXd target;  // N (force) or m (shift), operator components
};

// This rank's slab of a serial field.
Field slab(const HalfSpace& hd, const Field& f) {
  return f.middleCols(hd.first_row(), hd.local_rows());
}

// Largest difference over all ranks between a distributed slab and the serial field.
double slab_difference(const HalfSpace& hd, const Field& distributed, const Field& serial) {
  const Field mine = slab(hd, serial);
  return hd.communicator().max(mine.size() ? (distributed - mine).abs().maxCoeff() : 0.0);
}

// Stick inside the disc, slip on it, open off contact (the stiffness solve reads stick only).
StateField stick_state(const Field& bound, const VecField& tau) {
  Field mag = tau[0].square();
  for (std::size_t c = 1; c < tau.size(); ++c) mag += tau[c].square();
  mag = mag.sqrt();
  StateField s(bound.rows(), bound.cols());
  for (Eigen::Index k = 0; k < s.size(); ++k)
    s(k) = std::uint8_t(!(bound(k) > 0.0)                     ? NodeState::open
                        : mag(k) < bound(k) * (1 - kBoundEps) ? NodeState::stick
                                                              : NodeState::slip);
  return s;
}

std::unique_ptr<TangentialSolver> make_solver(TangentialOperator& op, Algorithm a,
                                              Precondition pre) {
  const TangentialOptions opt{1e-13, 5000, pre};
  if (a == Algorithm::partition) return std::make_unique<PartitionSolver>(op, opt);
  return std::make_unique<ProjectedCgSolver>(op, opt);
}

// Hertz sphere R = 10 mm on a 1 mm free grid of n x n nodes pressed by 1 kN (contact radius
// ~L/3), steel; the increments `loads` solved serially and on the ranks, compared after each.
void expect_same_history(int n, Coupling coupling, Algorithm algorithm, Precondition pre,
                         const std::vector<Load>& loads) {
  const Communicator& world = world_communicator();
  const Grid grid = Grid::square(n, 1e-3);
  const Material m{Body{210e9, 0.3}, std::nullopt, kMu};
  HalfSpace hs(grid, m, coupling);
  HalfSpace hd(grid, m, coupling, {}, world);
  Field z(n, n), p;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) z(i, j) = -(grid.x(i) * grid.x(i) + grid.y(j) * grid.y(j)) / 2e-2;
  NormalSolver(hs, NormalOptions{1e-13, 4000}).solve_force(z, 1e3, p);
  const Field bound_s = kMu * p, bound_d = slab(hd, bound_s);
  const int nc = int(loads.front().target.size());
  auto op_s = nc == 1 ? TangentialOperator(hs, Vec2(1, 0)) : TangentialOperator(hs);
  auto op_d = nc == 1 ? TangentialOperator(hd, Vec2(1, 0)) : TangentialOperator(hd);
  auto ss = make_solver(op_s, algorithm, pre), sd = make_solver(op_d, algorithm, pre);
  StiffnessSolver ks(op_s, 1e-12, 2000, pre), kd(op_d, 1e-12, 2000, pre);
  VecField tau_s = op_s.zeros(), u_s = op_s.zeros(), tau_d = op_d.zeros(), u_d = op_d.zeros();
  for (std::size_t step = 0; step < loads.size(); ++step) {
    const VecField t0s = tau_s, u0s = u_s, t0d = tau_d, u0d = u_d;
    const TangentialIncrement is{&bound_s, &t0s, &u0s, loads[step].control, loads[step].target};
    const TangentialIncrement id{&bound_d, &t0d, &u0d, loads[step].control, loads[step].target};
    const TangentialResult rs = ss->solve(is, tau_s, u_s);
    const TangentialResult rd = sd->solve(id, tau_d, u_d);
    for (int c = 0; c < nc; ++c) {
      EXPECT_LT(slab_difference(hd, tau_d[c], tau_s[c]) / bound_s.maxCoeff(), kTolerance)
          << "step " << step << " component " << c;
      EXPECT_LT(slab_difference(hd, u_d[c], u_s[c]) / u_s[c].abs().maxCoeff(), kTolerance)
          << "step " << step << " component " << c;
      const double F = kMu * 1e3;  // the full-sliding force: the force's scale
      EXPECT_NEAR(rd.force(c), rs.force(c), kTolerance * F) << "step " << step;
      EXPECT_NEAR(rd.shift(c), rs.shift(c), kTolerance * u_s[c].abs().maxCoeff())
          << "step " << step;
    }
    EXPECT_TRUE(rd.converged);
    const StateField state = stick_state(bound_s, tau_s);
    const StateField state_d = state.middleCols(hd.first_row(), hd.local_rows());
    const StiffnessResult kxs = ks.solve(state), kxd = kd.solve(state_d);
    EXPECT_NEAR(kxd.kx, kxs.kx, kTolerance * kxs.kx) << "step " << step;
    EXPECT_EQ(kxd.preconditioned, kxs.preconditioned);
  }
}

Eigen::VectorXd x(double v) {
  return Eigen::VectorXd::Constant(1, v);
}

// Cattaneo ramp to 0.8 mu F_z, then a Mindlin reversal to -0.8 mu F_z and back to 0.4 mu F_z
// (force control, N).
std::vector<Load> mindlin_forces(int nc) {
  std::vector<Load> loads;
  for (const double q : {0.3, 0.6, 0.8, 0.4, 0.0, -0.5, -0.8, 0.4}) {
    Eigen::VectorXd F = Eigen::VectorXd::Zero(nc);
    F(0) = q * kMu * 1e3;
    if (nc == 2) F(1) = 0.5 * F(0);  // a load off the x axis: both components work
    loads.push_back({TangentialControl::force, F});
  }
  return loads;
}

// The same cycle under displacement control: increments of the rigid shift (m). Full sliding
// at this contact is a shift of ~5.8 um (mu d E*/G*, d = a^2 / R ~ 16 um), so the ramp stays
// in partial slip, reverses and reloads.
std::vector<Load> mindlin_shifts() {
  std::vector<Load> loads;
  for (const double du : {1.5e-6, 1.5e-6, 1.5e-6, -2.5e-6, -2.5e-6, -2.5e-6, 4e-6})
    loads.push_back({TangentialControl::displacement, x(du)});
  return loads;
}

}  // namespace

TEST(TangentialSolverMpi, CattaneoMindlinForceControlEqualsSerial) {
  if (!mpi_test::on_ranks()) return mpi_test::run_on_ranks(2);
  expect_same_history(32, Coupling::analogy, Algorithm::projected, Precondition::off,
                      mindlin_forces(1));
}

TEST(TangentialSolverMpi, DisplacementControlEqualsSerial) {
  if (!mpi_test::on_ranks()) return mpi_test::run_on_ranks(2);
  expect_same_history(32, Coupling::analogy, Algorithm::projected, Precondition::off,
                      mindlin_shifts());
}

TEST(TangentialSolverMpi, PreconditionedAndAutomaticEqualSerial) {
  if (!mpi_test::on_ranks()) return mpi_test::run_on_ranks(2);
  expect_same_history(32, Coupling::analogy, Algorithm::projected, Precondition::on,
                      mindlin_forces(1));
  expect_same_history(32, Coupling::analogy, Algorithm::projected, Precondition::automatic,
                      mindlin_shifts());
}

TEST(TangentialSolverMpi, CerrutiTwoComponentsEqualsSerial) {
  if (!mpi_test::on_ranks()) return mpi_test::run_on_ranks(2);
  expect_same_history(32, Coupling::cerruti, Algorithm::projected, Precondition::off,
                      mindlin_forces(2));
}

TEST(TangentialSolverMpi, PartitionMethodEqualsSerial) {
  if (!mpi_test::on_ranks()) return mpi_test::run_on_ranks(2);
  expect_same_history(32, Coupling::analogy, Algorithm::partition, Precondition::off,
                      mindlin_forces(1));
}

// Three ranks on 31 rows: slabs of 11, 11 and 9 rows.
TEST(TangentialSolverMpi, UnevenSlabsOnThreeRanksEqualSerial) {
  if (!mpi_test::on_ranks()) return mpi_test::run_on_ranks(3);
  expect_same_history(31, Coupling::analogy, Algorithm::projected, Precondition::off,
                      mindlin_forces(1));
  expect_same_history(31, Coupling::cerruti, Algorithm::projected, Precondition::off,
                      mindlin_forces(2));
}
