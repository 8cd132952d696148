// Solvers that cannot stall (ctest label `stress`): the states that can stall
// them — a worn conforming annulus, a force reversal near sliding, gross slip under
// displacement control — and the failure contract (step, cycle and failed_solve.h5 named).
// Reference solutions come from an independent route: the constructed exact pressure, the
// other tangential algorithm, or the cold start.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "fretbem/contact/normal_solver.hpp"
#include "fretbem/contact/tangential_solver.hpp"
#include "fretbem/core/errors.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/history/stepper.hpp"
#include "fretbem/io/failed_solve.hpp"
#include "fretbem/surface/surface.hpp"
#include "fretbem/wear/integrator.hpp"
#include "support/hertz.hpp"
#include "support/temp_dir.hpp"

using namespace fretbem;
namespace fs = std::filesystem;

namespace {

// A worn sphere: E = 200 GPa, nu = 0.3, R = 10 mm, L = 1 mm, F_z = 457.875 N (contact
// radius a quarter of the domain), n = 64.
struct WornSphere {
  Grid grid = Grid::square(64, 1e-3);
  Material mat;
  std::unique_ptr<HalfSpace> hs;
  Field z_worn, p_exact, p_unworn;
  double Fz = 457.875;

  // The worn end state of Popov's limit built exactly: the pressure p_c of a Hertz disc of
  // radius c = a/2 (any positive pressure on the disc would do) displaces u_c = K p_c; the
  // surface z = u_c - (r - a)_+^2 / (2R) then touches with gap exactly 0 on the whole disc
  // r < a (p > 0 on r < c, p = 0 on the conforming annulus c < r < a) and opens outside, so
  // p_c is the unique solution at its force (K is positive definite).
  WornSphere() {
    mat.body1 = Body{200e9, 0.3};
    hs = std::make_unique<HalfSpace>(grid, mat, Coupling::analogy);
    const double R = 0.01, a = 0.25e-3, c = a / 2;
    p_exact = grid.zeros();
    for (int i = 0; i < grid.nx; ++i)
      for (int j = 0; j < grid.ny; ++j) {
        const double r = std::hypot(grid.x(i), grid.y(j));
        if (r < c) p_exact(i, j) = std::sqrt(1 - r * r / (c * c));
      }
    p_exact *= Fz / (p_exact.sum() * grid.cell_area());
    Field u;
    hs->normal(p_exact, u);
    z_worn = u;
    for (int i = 0; i < grid.nx; ++i)
      for (int j = 0; j < grid.ny; ++j) {
        const double r = std::hypot(grid.x(i), grid.y(j));
        if (r > a) z_worn(i, j) -= (r - a) * (r - a) / (2 * R);
      }
    // The warm start of the stall: the unworn sphere's pressure, thousands of annulus nodes
    // loaded that must leave contact.
    NormalSolver ns(*hs, {1e-10, 2000, Precondition::off});
    ns.solve_force(sphere_surface(grid, R), Fz, p_unworn);
  }
};

double rel_l2(const Field& a, const Field& b) {
  return std::sqrt((a - b).square().sum() / b.square().sum());
}

// Normal CG warm-started from the unworn pressure on the worn conforming annulus reaches the
// constructed pressure; the cold start reaches the same one (the wear map must not depend on
// the warm start). Tolerance: the solver's 1e-10 gap residual bounds the pressure error by
// the conditioning of K on the contact set (~n), so 1e-6 is far above round-off and far
// below a wrong contact set (one wrong annulus node would be ~1e-3).
TEST(SolverRobustness, NormalWarmStartOnWornConformingAnnulus) {
  WornSphere w;
  ASSERT_GT((w.p_unworn > 0).count() - (w.p_exact > 0).count(), 300);
  for (const Precondition pre : {Precondition::off, Precondition::on}) {
    NormalSolver ns(*w.hs, {1e-10, 2000, pre});
    Field warm = w.p_unworn, cold;
    const NormalResult rw = ns.solve_force(w.z_worn, w.Fz, warm);
    ns.solve_force(w.z_worn, w.Fz, cold);
    EXPECT_TRUE(rw.converged);
    EXPECT_LT(rel_l2(warm, w.p_exact), 1e-6);
    EXPECT_LT(rel_l2(cold, w.p_exact), 1e-6);
  }
}

// Force reversals near sliding (+-0.875 mu F_z) on the worn annulus and on the unworn
// sphere, preconditioned and plain, within a budget of 500 iterations; the
// partition algorithm (a different iteration on the same strictly convex QP) gives the same
// traction.
TEST(SolverRobustness, ForceReversalsNearSlidingConverge) {
  WornSphere w;
  const double mu = 0.5;
  TangentialOperator op(*w.hs, Vec2(1, 0));
  for (const Field* p : {&w.p_exact, &w.p_unworn}) {
    const Field bound = mu * *p;
    for (const Precondition pre : {Precondition::off, Precondition::on}) {
      TangentialOptions opt{1e-9, 500, pre};
      ProjectedCgSolver pcg(op, opt);
      PartitionSolver part(op, {1e-9, 5000, Precondition::off});
      VecField tau = op.zeros(), u = op.zeros(), tau_p = tau, u_p = u;
      for (const double q : {0.875, -0.875, 0.875, -0.5}) {
        TangentialIncrement inc;
        const VecField tau0 = tau, u0 = u, tau0_p = tau_p, u0_p = u_p;
        inc.bound = &bound, inc.tau0 = &tau0, inc.u0 = &u0;
        inc.control = TangentialControl::force;
        inc.target = Eigen::VectorXd::Constant(1, q * mu * w.Fz);
        const TangentialResult r = pcg.solve(inc, tau, u);
        EXPECT_TRUE(r.converged);
        EXPECT_LT(r.iterations, 200) << "q = " << q;
        inc.tau0 = &tau0_p, inc.u0 = &u0_p;
        part.solve(inc, tau_p, u_p);
        EXPECT_LT(rel_l2(tau[0], tau_p[0]), 1e-5) << "q = " << q;
      }
    }
  }
}

Scenario scenario(const std::string& text) {
  return parse_scenario(text, "robustness", fs::temp_directory_path());
}

int fallbacks(const Model& m) {
  return dynamic_cast<const FallbackTangentialSolver&>(*m.tangential).fallbacks();
}

// A steel ball in gross slip under displacement control (1.7x the full-sliding shift, 64
// steps per cycle, n = 128): every step, the first reversal (step 17) included, must converge with
// the projected method alone (no fallback), the force saturating at mu F_z.
TEST(SolverRobustness, GrossSlipUnderDisplacementControl) {
  auto m = build_model(scenario(R"([material]
E = 210e9
nu = 0.3
E2 = 210e9
nu2 = 0.3
mu = 0.7
[grid]
n = 128
length = 0.37e-3
[surface]
type = sphere
radius = 6e-3
[load]
normal_force = 20
path = sine
control = displacement
displacement_amplitude = 2e-6
cycles = 1
steps_per_cycle = 64
[solver]
stiffness = false
)"));
  Stepper st(*m);
  struct MaxF : Observer {
    double fx = 0.0;
    void on_step(const StepRecord& r, const InterfaceState&, const Model&) override {
      fx = std::max(fx, std::abs(r.Fx));
    }
  } obs;
  st.run({&obs});
  EXPECT_EQ(fallbacks(*m), 0);
  EXPECT_NEAR(obs.fx, 0.7 * 20, 1e-6 * 14);
}

// A worn annulus on which the iteration can stall without its restarts (measured: N = 148 at
// n = 64, wear.integrator = cycle, max_iterations = 500, twice the wear coefficient of the
// smallest such case: the same worn states at half the cycles). Runs through N = 160 with the
// projected method alone.
TEST(SolverRobustness, WearReversalsOnTheWornAnnulus) {
  Scenario sc = scenario(R"([material]
E = 200e9
nu = 0.3
mu = 0.5
[grid]
n = 64
length = 1e-3
[surface]
type = sphere
radius = 0.01
[load]
normal_force = 457.875
path = sine
control = force
amplitude = 0.875
cycles = 1
steps_per_cycle = 4
[solver]
stiffness = false
tolerance = 1e-9
max_iterations = 500
[wear]
law = archard
coefficient = 9e-13
cycles = 160
integrator = cycle
)");
  auto m = build_model(sc);
  Stepper st(*m);
  WearCycles cycles(*m, st);  // no observers: the solves alone, no output files
  Observer silent;
  EXPECT_NO_THROW(integrate_wear(*m, cycles, silent));
  EXPECT_EQ(fallbacks(*m), 0);
}

// A solver that never converges: the failure names step and cycle and carries the inputs,
// which write_failed_solve stores in DIR/failed_solve.h5.
struct NeverConverges : TangentialSolver {
  TangentialResult solve(const TangentialIncrement&, VecField&, VecField&) override {
    throw SolverError("test solver did not converge");
  }
};

TEST(SolverRobustness, FailedSolveNamesStepCycleAndDumpsInputs) {
  Scenario sc = scenario(fretbem_test::kSteelSphere32 + R"(path = sine
control = force
amplitude = 0.5
cycles = 2
steps_per_cycle = 4
[solver]
stiffness = false
)");
  const fretbem_test::TempDir tmp("failed_solve");
  sc.output.dir = tmp / "run";
  auto m = build_model(sc);
  m->tangential = std::make_unique<NeverConverges>();
  Stepper st(*m);
  st.advance(0);
  try {
    st.advance(1);
    FAIL() << "no failure";
  } catch (const IncrementFailure& e) {
    EXPECT_NE(std::string(e.what()).find("step 1, cycle 0: test solver"), std::string::npos)
        << e.what();
    EXPECT_EQ(e.inputs.solve, "tangential");
    EXPECT_EQ(e.inputs.control, "force");
    ASSERT_EQ(e.inputs.bound.size(), 32 * 32);
    EXPECT_GT(e.inputs.bound.maxCoeff(), 0.0);
    const fs::path file = write_failed_solve(e.dir, e.inputs);
    EXPECT_EQ(file, sc.output.dir / "failed_solve.h5");
    const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    for (const char* name : {"inputs", "scenario", "bound", "tau0_0", "u0_0"})
      EXPECT_GT(H5Lexists(f, name, H5P_DEFAULT), 0) << name;
    H5Fclose(f);
  }
}

}  // namespace

// Robustness case 77 (rough surface, elastic indenter, Cerruti, force-controlled
// table with an oscillating normal force): at the load peak only 22 of 111 contact nodes
// stick, and a force correction applied after each slip-node step feeds back on the slip ring
// (residual +10 % per iteration). The slip-node step carries its own force correction, so
// every row must converge with the projected method alone, at the asked force.
TEST(SolverRobustness, FewStickNodesUnderForceControlWithCerruti) {
  const fretbem_test::TempDir tmp("case77");
  const fs::path& dir = tmp.path();
  std::ofstream(dir / "table.csv") << "time,Fz,Fx\n0,250.039,0\n1,258.64,35.1032\n"
                                      "2,265.355,70.645\n3,269.925,104.327\n4,272.175,133.89\n"
                                      "5,272.017,157.347\n6,269.459,173.19\n7,264.598,180.541\n"
                                      "8,257.621,179.224\n";
  auto m = build_model(parse_scenario(R"([material]
E = 2.1e+11
nu = 0.3
mu = 0.848509
E2 = 3.85013e+11
nu2 = 0.270057
[grid]
n = 48
length = 0.001
[surface]
type = rough
hurst = 0.545101
rms_slope = 0.066717
seed = 742
[load]
path = table
table = table.csv
control = force
[solver]
stiffness = false
coupling = cerruti
)",
                                      "case77", dir));
  Stepper st(*m);
  struct Rows : Observer {
    std::vector<StepRecord> rows;
    void on_step(const StepRecord& r, const InterfaceState&, const Model&) override {
      rows.push_back(r);
    }
  } obs;
  st.run({&obs});
  EXPECT_EQ(fallbacks(*m), 0);
  ASSERT_EQ(obs.rows.size(), 9u);
  EXPECT_NEAR(obs.rows[7].Fx, 180.541, 1e-8 * 0.848509 * 264.598);
  EXPECT_NEAR(obs.rows[7].Fy, 0.0, 1e-8 * 0.848509 * 264.598);
}
