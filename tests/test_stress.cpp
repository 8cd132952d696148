// Numerical stress tests (ctest label `stress`). Quick versions of
// every case run here; the large ones (H = 0.1 at n = 512) are in tools/bench/stress.sh.
// Every case must converge or throw SolverError, keep |tau| <= mu p, and never produce NaN.
// Outcomes are documented in docs/stability.md.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "fretbem/contact/normal_solver.hpp"
#include "fretbem/contact/tangential_solver.hpp"
#include "fretbem/core/errors.hpp"
#include "fretbem/history/cost_estimate.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/history/stepper.hpp"
#include "fretbem/surface/surface.hpp"

using namespace fretbem;
namespace fs = std::filesystem;

namespace {

// Invariants of every step: finite fields, |tau| <= mu p (relative to max mu p; the solver
// projects onto the bound, so only round-off may exceed it), non-negative dissipation.
struct Checker : Observer {
  std::vector<StepRecord> rows;
  double violation = 0.0, min_dissipation_step = 0.0;
  bool finite = true;
  void on_step(const StepRecord& r, const InterfaceState& s, const Model& m) override {
    if (!rows.empty())
      min_dissipation_step =
          std::min(min_dissipation_step, r.dissipation - rows.back().dissipation);
    rows.push_back(r);
    Field mag = s.traction[0].square();
    for (std::size_t c = 1; c < s.traction.size(); ++c) mag += s.traction[c].square();
    const Field g = m.scenario.material.mu * s.pressure;
    if (g.maxCoeff() > 0)
      violation = std::max(violation, (mag.sqrt() - g).maxCoeff() / g.maxCoeff());
    finite &= s.pressure.allFinite();
    for (const auto& t : s.traction) finite &= t.allFinite();
    for (double v : {r.Fx, r.Fy, r.Ux, r.Uy, r.Fz, r.delta, r.dissipation})
      finite &= std::isfinite(v);
  }
};

Checker run(const std::string& text) {
  const Scenario sc = parse_scenario(text, "stress", fs::temp_directory_path());
  auto model = build_model(sc);
  Stepper stepper(*model);
  Checker c;
  stepper.run({&c});
  return c;
}

void expect_sane(const Checker& c, const std::string& what) {
  EXPECT_TRUE(c.finite) << what;
  EXPECT_LE(c.violation, 1e-12) << what;
  // Coulomb dissipation tau . s >= 0 per step, up to the solver tolerance times the work scale.
  const double scale = std::max(1e-300, std::abs(c.rows.back().dissipation));
  EXPECT_GE(c.min_dissipation_step, -1e-6 * scale) << what;
}

// Hertz sphere on a unit domain, contact radius 1/4 (R = 1), E = 1, nu = 0.3.
std::string sphere(int nx, int ny, double mu, const std::string& load,
                   const std::string& extra = "", double tol = 1e-10) {
  std::ostringstream s;
  s << std::setprecision(17) << "[material]\nE = 1\nnu = 0.3\nmu = " << mu << "\n"
    << extra << "[grid]\nnx = " << nx << "\nny = " << ny << "\nlength = 1\n"
    << "[surface]\ntype = sphere\nradius = 1\n[load]\n"
    << load << "\n[solver]\ntolerance = " << tol << "\nthreads = 1\n";
  return s.str();
}

std::string indentation(double d) {
  std::ostringstream s;
  s << std::setprecision(17) << "indentation = " << d << "\n";
  return s.str();
}

}  // namespace

// mu over four decades: a force-controlled cycle to +-0.9 mu F_z with the stiffness solve on.
TEST(Stress, FrictionCoefficientFrom1e3To10) {
  for (double mu : {1e-3, 1e-2, 0.1, 1.0, 10.0}) {
    const Checker c = run(sphere(
        32, 32, mu,
        indentation(1.0 / 16) + "path = sine\namplitude = 0.9\ncycles = 1\nsteps_per_cycle = 8"));
    expect_sane(c, "mu = " + std::to_string(mu));
    EXPECT_NEAR(c.rows[2].Fx, 0.9 * mu * c.rows[2].Fz, 1e-9 * mu * c.rows[2].Fz);
  }
}

// A very rough surface (H = 0.1: almost white roughness, many tiny contact spots) under a
// force-controlled sine; small n here, n = 512 in tools/bench/stress.sh.
TEST(Stress, RoughSurfaceHurst01) {
  const std::string text =
      "[material]\nE = 1\nnu = 0.3\nmu = 0.5\n[grid]\nn = 64\nlength = 1\n"
      "[surface]\ntype = rough\nhurst = 0.1\nrms_slope = 0.1\nmethod = fourier\nseed = 7\n"
      "[load]\nnormal_force = 0.0035\npath = sine\namplitude = 0.9\ncycles = 1\n"
      "steps_per_cycle = 8\n[solver]\ntolerance = 1e-10\nthreads = 1\n";
  for (const char* alg : {"projected", "partition"}) {
    const Checker c = run(text + "algorithm = " + alg + "\n");
    expect_sane(c, alg);
    EXPECT_GT(c.rows[0].contact_area, 0.0);
  }
}

// Force control up to 0.999 mu F_z (the stick zone shrinks to a few nodes), both algorithms.
TEST(Stress, ForceControlTo0999) {
  for (const char* alg : {"projected", "partition"}) {
    for (double q : {0.99, 0.999}) {
      std::ostringstream load;
      load << indentation(1.0 / 16) << "path = ramp\namplitude = " << q << "\nsteps = 3";
      const Checker c = run(sphere(64, 64, 0.5, load.str(), "", 1e-10) + "algorithm = " + alg);
      expect_sane(c, alg);
      const auto& last = c.rows.back();
      EXPECT_NEAR(last.Fx / (0.5 * last.Fz), q, 1e-9) << alg;
    }
  }
}

// Displacement control to 100x the full-sliding shift and back to -100x: the force saturates
// at +-mu F_z with every contact node slipping, and no stick area remains.
TEST(Stress, DisplacementFarPastFullSliding) {
  const double slide = 0.5 * (1.0 / 16) * 2 * (1 - 0.3) / (2 - 0.3);  // mu delta E*/G*
  std::ostringstream load;
  load << indentation(1.0 / 16)
       << "path = sine\ncontrol = displacement\ndisplacement_amplitude = " << 100 * slide
       << "\ncycles = 1\nsteps_per_cycle = 4"
       << "\nallow_large_shift = true";  // 10 contact radii: the solver's limit, not fretting
  const Checker c = run(sphere(64, 64, 0.5, load.str()));
  expect_sane(c, "displacement");
  EXPECT_NEAR(c.rows[1].Fx, 0.5 * c.rows[1].Fz, 1e-9 * c.rows[1].Fz);
  EXPECT_NEAR(c.rows[3].Fx, -0.5 * c.rows[3].Fz, 1e-9 * c.rows[3].Fz);
  EXPECT_EQ(c.rows[1].stick_area, 0.0);
  EXPECT_EQ(c.rows[3].stick_area, 0.0);
}

// 1000 tiny increments against one increment to the same shift on a monotone segment: the
// incremental solution does not depend on the step size, so there must be no drift.
TEST(Stress, ThousandTinyIncrementsNoDrift) {
  const Grid grid = Grid::square(32, 1.0);
  Material mat;
  mat.body1 = {1.0, 0.3};
  HalfSpace hs(grid, mat, Coupling::analogy);
  NormalSolver ns(hs, {1e-12, 5000});
  Field p;
  ns.solve_indentation(sphere_surface(grid, 1.0), 1.0 / 16, p);
  const Field bound = 0.5 * p;
  TangentialOperator op(hs, Vec2(1, 0));
  const double U = 0.8 * 0.5 * (1.0 / 16) * hs.tangential_ratio();
  for (const bool partition : {false, true}) {
    std::unique_ptr<TangentialSolver> s;
    if (partition)
      s = std::make_unique<PartitionSolver>(op, TangentialOptions{1e-12, 5000});
    else
      s = std::make_unique<ProjectedCgSolver>(op, TangentialOptions{1e-12, 5000});
    auto step = [&](double dU, VecField& tau, VecField& u) {
      const VecField t0 = tau, u0 = u;
      TangentialIncrement inc{&bound, &t0, &u0, TangentialControl::displacement,
                              Eigen::VectorXd::Constant(1, dU)};
      s->solve(inc, tau, u);
    };
    VecField t1 = op.zeros(), u1 = op.zeros(), tk = op.zeros(), uk = op.zeros();
    step(U, t1, u1);
    for (int k = 0; k < 1000; ++k) step(U / 1000, tk, uk);
    const double rel = std::sqrt((tk[0] - t1[0]).square().sum() / t1[0].square().sum());
    std::printf("%s: 1000 increments vs 1: relative L2 traction difference %.2e\n",
                partition ? "partition" : "projected", rel);
    EXPECT_LE(rel, 1e-6);
    EXPECT_LE((tk[0].abs() - bound).maxCoeff(), 1e-14 * bound.maxCoeff());
  }
}

// A load reversal at every step, with a slowly shrinking amplitude: each increment first
// re-sticks the whole contact, then slips the opposite way.
TEST(Stress, ReversalAtEveryStep) {
  const Grid grid = Grid::square(48, 1.0);
  Material mat;
  mat.body1 = {1.0, 0.3};
  HalfSpace hs(grid, mat, Coupling::analogy);
  NormalSolver ns(hs, {1e-12, 5000});
  Field p;
  const double Fz = ns.solve_indentation(sphere_surface(grid, 1.0), 1.0 / 16, p).force;
  const double mu = 0.5;
  const Field bound = mu * p;
  TangentialOperator op(hs, Vec2(1, 0));
  for (const bool partition : {false, true}) {
    std::unique_ptr<TangentialSolver> s;
    if (partition)
      s = std::make_unique<PartitionSolver>(op, TangentialOptions{1e-10, 5000});
    else
      s = std::make_unique<ProjectedCgSolver>(op, TangentialOptions{1e-10, 5000});
    VecField tau = op.zeros(), u = op.zeros();
    for (int k = 0; k < 40; ++k) {
      const double q = (k % 2 ? -1.0 : 1.0) * (0.95 - 0.02 * k);
      const VecField t0 = tau, u0 = u;
      TangentialIncrement inc{&bound, &t0, &u0, TangentialControl::force,
                              Eigen::VectorXd::Constant(1, q * mu * Fz)};
      const auto r = s->solve(inc, tau, u);
      ASSERT_TRUE(r.converged);
      EXPECT_NEAR(r.force(0), q * mu * Fz, 1e-9 * mu * Fz);
      EXPECT_TRUE(tau[0].allFinite());
      EXPECT_LE((tau[0].abs() - bound).maxCoeff(), 1e-14 * bound.maxCoeff());
    }
  }
}

// Near-zero normal load: on an odd grid the sphere's apex is one node; a tiny force touches
// only it. It sticks, then slips at mu p; force control at mu F_z is refused loudly.
TEST(Stress, NearZeroNormalLoadOneNode) {
  const Checker c = run(sphere(33, 33, 0.5,
                               "normal_force = 1e-12\npath = sine\namplitude = 0.9\ncycles = 1\n"
                               "steps_per_cycle = 8"));
  expect_sane(c, "one node");
  const double h = 1.0 / 33;
  EXPECT_NEAR(c.rows[0].contact_area, h * h, 1e-12 * h * h);
  EXPECT_NEAR(c.rows[2].Fx, 0.9 * 0.5 * 1e-12, 1e-9 * 0.5e-12);
  EXPECT_THROW(run(sphere(33, 33, 0.5,
                          "normal_force = 1e-12\npath = ramp\namplitude = 1.0\n"
                          "steps = 2")),
               std::exception);  // InputError (amplitude must be < 1) or SolverError
}

// E contrast 1e6 between the bodies, both ways round: E* is set by the softer body, and the
// tangential ratio E*/G* by its Poisson ratio. Mindlin–Deresiewicz cycles must still close.
TEST(Stress, ModulusContrast1e6) {
  for (const char* e2 : {"E2 = 1e6\nnu2 = 0.2\n", "E2 = 1e-6\nnu2 = 0.2\n"}) {
    // Indentation control: the contact radius stays L/4 whatever E* is.
    const Checker c = run(sphere(
        48, 48, 0.5,
        indentation(1.0 / 16) + "path = sine\namplitude = 0.7\ncycles = 2\nsteps_per_cycle = 8",
        e2));
    expect_sane(c, e2);
    EXPECT_GT(c.rows.back().dissipation, 0.0) << e2;
  }
}

// Non-square and odd grids (the FFT padding is 2nx x 2ny with odd sides): symmetric load gives
// a symmetric answer, and the invariants hold; the same load on the transposed grid gives the
// same forces and shifts.
TEST(Stress, NonSquareAndOddGrids) {
  const std::string load =
      indentation(1.0 / 64) + "path = sine\namplitude = 0.8\ncycles = 1\nsteps_per_cycle = 8";
  const Checker a = run(sphere(45, 33, 0.5, load));
  const Checker b = run(sphere(33, 45, 0.5, load));
  expect_sane(a, "45x33");
  expect_sane(b, "33x45");
  // Different domains (length is along x), so compare each with its own Fz: same q reached.
  for (std::size_t k = 1; k < a.rows.size(); ++k) {
    EXPECT_NEAR(a.rows[k].Fx / a.rows[k].Fz, b.rows[k].Fx / b.rows[k].Fz, 1e-9);
    EXPECT_GT(a.rows[k].contact_area, 0.0);
  }
  const Checker c = run(sphere(31, 31, 0.5, load + "\ndirection = 30"));
  expect_sane(c, "31x31 at 30 degrees");
  EXPECT_NEAR(c.rows[2].Fy / c.rows[2].Fx, std::tan(M_PI / 6), 1e-8);
}

// A grid that cannot fit in memory is refused before anything is allocated, in one line.
TEST(Stress, HugeGridRefusedBeforeAllocating) {
  const std::string text =
      "[material]\nE = 1\nnu = 0.3\n[grid]\nn = 16384\nlength = 1\n[surface]\ntype = flat\n"
      "[load]\nnormal_force = 1\n";
  const Scenario sc = parse_scenario(text, "huge", fs::temp_directory_path());
  EXPECT_GT(estimate_memory(sc, false).total(), 1.5e11);
  try {
    build_model(sc);
    ADD_FAILURE() << "no error for a 16384^2 grid";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    std::printf("%s\n", msg.c_str());
    EXPECT_NE(msg.find("GiB"), std::string::npos);
    EXPECT_EQ(msg.find('\n'), std::string::npos);
  }
}
