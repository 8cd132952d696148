// Validation rung 2 (docs/architecture.md, "Validation ladder"): the Polonsky–Keer normal solver
// against closed forms (Hertz; the rigid flat square punch through its electrostatic analogue), its
// reporting and error contract, and convergence on a rough surface.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "fretbem/contact/cg_core.hpp"
#include "fretbem/contact/normal_solver.hpp"
#include "fretbem/core/errors.hpp"
#include "fretbem/elastic/closed_forms.hpp"
#include "fretbem/elastic/grid.hpp"
#include "fretbem/elastic/half_space.hpp"
#include "fretbem/elastic/material.hpp"
#include "fretbem/surface/surface.hpp"

namespace fretbem {
namespace {

constexpr double pi = std::numbers::pi;

Material single_body(double E, double nu) {
  Material m;
  m.body1 = Body{E, nu};
  return m;
}

// Hertz, sphere of radius R on a half-space of modulus E* (Johnson §4.2):
// a^2 = R delta, F = 4 E* a^3 / (3 R), p(r) = p0 sqrt(1 - r^2/a^2), p0 = 2 E* a / (pi R).
struct Hertz {
  double E_star, R, a;
  double delta() const { return closed_forms::hertz_approach(a, R); }
  double force() const { return closed_forms::hertz_force(a, R, E_star); }
  double p0() const { return 2 * E_star * a / (pi * R); }
  double pressure(double r) const { return r < a ? p0() * std::sqrt(1 - r * r / (a * a)) : 0.0; }
  double area() const { return pi * a * a; }
};

// The geometry shared by the Hertz tests: domain L = 1 mm, contact diameter L/2 (as the
// foundation issue asks), steel-like half-space, rigid sphere.
constexpr double kL = 1e-3, kR = 0.05;
const Material kSteel = single_body(210e9, 0.3);
Hertz hertz_for(const Material& m) {
  return Hertz{m.E_star(), kR, kL / 4};
}

// The sphere's highest cells sit at r = h/sqrt(2) (no node at the apex for even n), so the
// solver's indentation, measured from first touch at z_max, is Hertz's minus |z_max|. This is
// geometry of the discretised indenter, not a fitted correction.
double solver_delta(const Field& z, double hertz_delta) {
  return hertz_delta + z.maxCoeff();
}

struct HertzRun {
  double delta_err, p_apex_err, area_err, force;
  NormalResult res;
};

// Force control at Hertz's load: relative errors of indentation, pressure at the cell nearest
// the apex (against the closed form at that cell's centre) and contact area.
HertzRun hertz_force_control(int n, const Material& mat = kSteel) {
  const Grid grid = Grid::square(n, kL);
  const Hertz hz = hertz_for(mat);
  HalfSpace hs(grid, mat, Coupling::analogy);
  NormalSolver solver(hs);
  const Field z = sphere_surface(grid, kR);
  Field p;
  HertzRun run{};
  run.res = solver.solve_force(z, hz.force(), p);
  const double d_ref = solver_delta(z, hz.delta());
  run.delta_err = std::fabs(run.res.indentation - d_ref) / d_ref;
  const int c = n / 2;  // cells c-1 and c straddle the apex; (c, c) is one of the four nearest
  const double r = std::hypot(grid.x(c), grid.y(c));
  run.p_apex_err = std::fabs(p(c, c) - hz.pressure(r)) / hz.pressure(r);
  run.area_err = std::fabs((p > 0).count() * grid.cell_area() - hz.area()) / hz.area();
  run.force = run.res.force;
  return run;
}

// Tolerances for n = 128 (a = 32 h). Piecewise-constant pressure with collocation at the cell
// centres is second-order accurate in h/a away from the contact edge, where p ~ sqrt(a - r)
// limits the integrated quantities to O((h/a)^{3/2}) ~ 6e-3 times a constant well below 1:
// the 0.1 % for force, indentation and apex pressure. The contact area counts whole
// cells: the edge band holds 2 pi a h cells' worth of area, 2 h/a = 6 % of pi a^2, and the
// rounding in and out of a smooth circle cancels to a fraction of that; 2.5 % as asked.
constexpr double kHertzTol = 1e-3, kAreaTol = 2.5e-2;

TEST(NormalSolverHertz, ForceForGivenIndentation) {
  const int n = 128;
  const Grid grid = Grid::square(n, kL);
  const Hertz hz = hertz_for(kSteel);
  HalfSpace hs(grid, kSteel, Coupling::analogy);
  NormalSolver solver(hs);
  const Field z = sphere_surface(grid, kR);
  Field p;
  const NormalResult res = solver.solve_indentation(z, solver_delta(z, hz.delta()), p);
  EXPECT_TRUE(res.converged);
  EXPECT_NEAR(res.force, hz.force(), kHertzTol * hz.force());
  EXPECT_NEAR(res.force, p.sum() * grid.cell_area(), 1e-12 * res.force);
  const int c = n / 2;
  const double r = std::hypot(grid.x(c), grid.y(c));
  EXPECT_NEAR(p(c, c), hz.pressure(r), kHertzTol * hz.pressure(r));
  RecordProperty("force_rel_err", std::to_string(std::fabs(res.force / hz.force() - 1)));
}

TEST(NormalSolverHertz, IndentationAreaAndApexPressureForGivenForce) {
  const HertzRun run = hertz_force_control(128);
  EXPECT_TRUE(run.res.converged);
  EXPECT_LE(run.delta_err, kHertzTol);
  EXPECT_LE(run.p_apex_err, kHertzTol);
  EXPECT_LE(run.area_err, kAreaTol);
  EXPECT_NEAR(run.force, hertz_for(kSteel).force(), 1e-12 * run.force);  // force is imposed
  RecordProperty("delta_rel_err", std::to_string(run.delta_err));
  RecordProperty("p_apex_rel_err", std::to_string(run.p_apex_err));
  RecordProperty("area_rel_err", std::to_string(run.area_err));
  RecordProperty("iterations", run.res.iterations);
  RecordProperty("convolutions", run.res.convolutions);
}

TEST(NormalSolverHertz, ErrorsFallWithGridRefinement) {
  std::vector<HertzRun> runs;
  for (int n : {64, 128, 256}) runs.push_back(hertz_force_control(n));
  for (std::size_t k = 1; k < runs.size(); ++k) {
    EXPECT_LT(runs[k].delta_err, runs[k - 1].delta_err) << "refinement step " << k;
    EXPECT_LT(runs[k].p_apex_err, runs[k - 1].p_apex_err) << "refinement step " << k;
  }
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const std::string n = std::to_string(64 << k);
    RecordProperty("delta_rel_err_n" + n, std::to_string(runs[k].delta_err));
    RecordProperty("p_apex_rel_err_n" + n, std::to_string(runs[k].p_apex_err));
    RecordProperty("area_rel_err_n" + n, std::to_string(runs[k].area_err));
  }
}

// Two elastic bodies: the solver sees only E* = 1/((1-nu1^2)/E1 + (1-nu2^2)/E2), so the
// two-body contact equals one body of modulus E* and nu = 0, and matches Hertz with that E*.
TEST(NormalSolverHertz, TwoBodiesUseTheEffectiveModulus) {
  Material two = single_body(210e9, 0.3);
  two.body2 = Body{70e9, 0.33};
  const double E_star = 1.0 / ((1 - 0.3 * 0.3) / 210e9 + (1 - 0.33 * 0.33) / 70e9);
  ASSERT_NEAR(two.E_star(), E_star, 1e-14 * E_star);
  const Material one = single_body(E_star, 0.0);

  const int n = 64;
  const Grid grid = Grid::square(n, kL);
  const Field z = sphere_surface(grid, kR);
  const Hertz hz{E_star, kR, kL / 4};
  HalfSpace hs2(grid, two, Coupling::analogy), hs1(grid, one, Coupling::analogy);
  NormalSolver s2(hs2), s1(hs1);
  Field p2, p1;
  const NormalResult r2 = s2.solve_indentation(z, solver_delta(z, hz.delta()), p2);
  s1.solve_indentation(z, solver_delta(z, hz.delta()), p1);
  // Same linear operator up to the rounding of E*: the solutions agree to the solver tolerance.
  EXPECT_LE((p2 - p1).abs().maxCoeff(), 1e-8 * p1.maxCoeff());
  // n = 64 (a = 16 h): the O((h/a)^{3/2}) edge error estimate gives ~4x the n = 128 bound.
  EXPECT_NEAR(r2.force, hz.force(), 4 * kHertzTol * hz.force());
}

// Rigid flat square punch of side L pressed by delta, covering the whole grid. No closed form
// exists for the square; by the electrostatic analogy (u = (1/(pi E*)) int p/r, equipotential
// disc <-> punch) the force is F = pi C E* L delta, C = 0.3667874 the capacitance of the unit
// square plate in units of 4 pi eps0 (F. H. Read, J. Comput. Phys. 133 (1997) 1; the disc
// check: C = 2a/pi gives Sneddon's F = 2 E* a delta). So F / (E* L delta) = 1.152297.
// The edge singularity p ~ d^{-1/2} makes the cell discretisation converge slowly, so the
// grid values are Richardson-extrapolated: F_h = F + c h^k with k estimated from three grids.
TEST(NormalSolverPunch, FlatSquarePunchForceMatchesCapacitanceOfSquare) {
  const double reference = pi * 0.3667874;
  const Material mat = single_body(210e9, 0.3);
  const double delta = 1e-7;
  std::vector<double> f;
  for (int n : {32, 64, 128}) {
    const Grid grid = Grid::square(n, kL);
    HalfSpace hs(grid, mat, Coupling::analogy);
    NormalSolver solver(hs);
    Field p;
    const NormalResult res = solver.solve_indentation(flat_surface(grid), delta, p);
    EXPECT_TRUE((p > 0).all()) << "the punch must be in full contact, n = " << n;
    f.push_back(res.force / (mat.E_star() * kL * delta));
    RecordProperty("punch_force_n" + std::to_string(n), std::to_string(f.back()));
  }
  // Error ratio (f1 - f0)/(f2 - f1) = 2^k; the extrapolated limit is f2 + (f2 - f1)/(2^k - 1).
  const double ratio = (f[1] - f[0]) / (f[2] - f[1]);
  ASSERT_GT(ratio, 1.0) << "the sequence must converge monotonically to extrapolate";
  const double limit = f[2] + (f[2] - f[1]) / (ratio - 1.0);
  RecordProperty("punch_order", std::to_string(std::log2(ratio)));
  RecordProperty("punch_extrapolated", std::to_string(limit));
  // The cell-based force converges from below (the discrete pressure cannot represent the
  // edge singularity) and the finest grid is within a few per cent (~sqrt(h/L) effect).
  EXPECT_LT(f[2], reference);
  EXPECT_NEAR(f[2], reference, 5e-2 * reference);
  // The extrapolation removes the O(h) term; what remains is the next term of the expansion
  // for an edge singularity, O(h^{3/2}), i.e. ~ sqrt(h/L) ~ 0.1 of the removed term's size
  // (f2 - f1 ~ 3e-3 relative) at n = 128: ~3e-4. Allow 1e-3.
  EXPECT_NEAR(limit, reference, 1e-3 * reference);
}

TEST(NormalSolverContract, WarmStartNeedsFewerIterations) {
  const Grid grid = Grid::square(128, kL);
  const Hertz hz = hertz_for(kSteel);
  HalfSpace hs(grid, kSteel, Coupling::analogy);
  NormalSolver solver(hs);
  const Field z = sphere_surface(grid, kR);
  Field p;
  solver.solve_force(z, hz.force(), p);
  Field warm = p, cold;
  const NormalResult rw = solver.solve_force(z, 1.05 * hz.force(), warm);
  const NormalResult rc = solver.solve_force(z, 1.05 * hz.force(), cold);
  EXPECT_LT(rw.iterations, rc.iterations);
  EXPECT_LE((warm - cold).abs().maxCoeff(), 1e-6 * cold.maxCoeff());
  RecordProperty("warm_iterations", rw.iterations);
  RecordProperty("cold_iterations", rc.iterations);
  // Indentation control with a warm start from the same solution converges as well.
  Field warm_d = p, cold_d, same = warm;
  const NormalResult rd = solver.solve_indentation(z, rw.indentation, warm_d);
  const NormalResult rdc = solver.solve_indentation(z, rw.indentation, cold_d);
  const NormalResult rs = solver.solve_force(z, 1.05 * hz.force(), same);
  const NormalResult rsd = solver.solve_indentation(z, rw.indentation, same);
  RecordProperty("warm_ind_iterations", rd.iterations);
  RecordProperty("cold_ind_iterations", rdc.iterations);
  RecordProperty("same_force_iterations", rs.iterations);
  RecordProperty("same_ind_iterations", rsd.iterations);
  EXPECT_LE((warm_d - warm).abs().maxCoeff(), 1e-6 * warm.maxCoeff());
  EXPECT_LT(rd.iterations, rdc.iterations);
  // A converged solution as warm start needs no CG step: the residual check at iteration 0
  // and the solver's verification re-convolution (which counts as iteration 1).
  EXPECT_LE(rs.iterations, 1);
  EXPECT_LE(rsd.iterations, 1);
}

// A warm start whose contact set the iteration cannot leave — all the force on one node far
// from the contact, where the gap on S is mean-free, hence zero, and the CG direction vanishes —
// still reaches the cold solution (the wear integrator's Newton iterates produced such starts).
TEST(NormalSolverContract, DegenerateWarmStartReachesTheSolution) {
  const Grid grid = Grid::square(64, kL);
  const Hertz hz = hertz_for(kSteel);
  HalfSpace hs(grid, kSteel, Coupling::analogy);
  NormalSolver solver(hs, {1e-10, 2000, Precondition::off});
  const Field z = sphere_surface(grid, kR);
  Field cold, warm = grid.zeros();
  solver.solve_force(z, hz.force(), cold);
  warm(0, 0) = hz.force() / grid.cell_area();
  const NormalResult r = solver.solve_force(z, hz.force(), warm);
  EXPECT_TRUE(r.converged);
  EXPECT_LE((warm - cold).abs().maxCoeff(), 1e-6 * cold.maxCoeff());
}

TEST(NormalSolverContract, ReportsIterationsResidualAndThrowsWhenNotConverged) {
  const Grid grid = Grid::square(64, kL);
  const Hertz hz = hertz_for(kSteel);
  HalfSpace hs(grid, kSteel, Coupling::analogy);
  const Field z = sphere_surface(grid, kR);
  NormalOptions opt;
  opt.tolerance = 1e-9;
  NormalSolver solver(hs, opt);
  Field p;
  const NormalResult res = solver.solve_force(z, hz.force(), p);
  EXPECT_TRUE(res.converged);
  EXPECT_GT(res.iterations, 0);
  EXPECT_LE(res.residual, opt.tolerance);
  EXPECT_GE(res.residual, 0.0);
  EXPECT_GT(res.convolutions, 0);
  EXPECT_TRUE((p >= 0).all());

  // Too few iterations for that tolerance: SolverError, whose message says why.
  NormalOptions few = opt;
  few.max_iterations = 3;
  NormalSolver starved(hs, few);
  Field q;
  EXPECT_THROW(starved.solve_force(z, hz.force(), q), SolverError);
  try {
    starved.solve_indentation(z, hz.delta(), q);
    ADD_FAILURE() << "expected SolverError";
  } catch (const SolverError& e) {
    EXPECT_NE(std::string(e.what()).find("did not converge"), std::string::npos) << e.what();
  }
}

TEST(NormalSolverContract, ZeroLoadGivesZeroPressure) {
  const Grid grid = Grid::square(32, kL);
  HalfSpace hs(grid, kSteel, Coupling::analogy);
  NormalSolver solver(hs);
  const Field z = sphere_surface(grid, kR);
  Field p = Field::Constant(grid.nx, grid.ny, 5.0);  // stale warm start must not leak through
  NormalResult res = solver.solve_force(z, 0.0, p);
  EXPECT_TRUE(res.converged);
  EXPECT_EQ(p.rows(), grid.nx);
  EXPECT_EQ(p.cols(), grid.ny);
  EXPECT_EQ(p.abs().maxCoeff(), 0.0);
  EXPECT_EQ(res.force, 0.0);
  p = Field::Constant(grid.nx, grid.ny, 5.0);
  res = solver.solve_indentation(z, 0.0, p);
  EXPECT_TRUE(res.converged);
  EXPECT_EQ(p.abs().maxCoeff(), 0.0);
}

// Independent check of a solution's complementarity: recompute u = K p with a fresh operator,
// take the gap g = u + (z_max - z) - delta, and measure the solver's residual definition
// (rms gap on the contact set plus rms penetration off it, over the rms displacement on it).
double kkt_residual(const Grid& grid, const Material& mat, const Field& z, const Field& p,
                    double delta) {
  HalfSpace hs(grid, mat, Coupling::analogy);
  Field u;
  hs.normal(p, u);
  const Field g = u + (z.maxCoeff() - z) - delta;
  const auto S = (p > 0);
  const double n = std::max<double>(1, S.count());
  const double on = S.select(g, 0.0).square().sum();
  const double off = S.select(0.0, g.min(0.0)).square().sum();
  const double scale = std::sqrt(S.select(u, 0.0).square().sum() / n);
  return std::sqrt((on + off) / n) / scale;
}

// A rough surface (H = 0.3, Fourier filtering, fixed seed) at n = 256 and its load: mean
// pressure ~ E* slope / 40, a contact fraction of a few per cent, many islands.
struct RoughCase {
  Grid grid = Grid::square(256, kL);
  Field z;
  double force = kSteel.E_star() * 0.05 / 40 * kL * kL;
  RoughCase() {
    RoughSpec spec;
    spec.hurst = 0.3;
    spec.method = RoughMethod::fourier;
    spec.rms_slope = 0.05;
    spec.seed = 20240601;
    z = rough_surface(grid, spec);
  }
};

// The rough case: the solver must reach the requested tolerance, and the solution must satisfy
// p >= 0 and complementarity when checked independently.
TEST(NormalSolverRough, ConvergesToRequestedTolerance) {
  const RoughCase rough;
  const Grid& grid = rough.grid;
  const Field& z = rough.z;
  const double force = rough.force;
  HalfSpace hs(grid, kSteel, Coupling::analogy);
  NormalOptions opt;  // default tolerance 1e-10
  NormalSolver solver(hs, opt);
  Field p;
  const NormalResult res = solver.solve_force(z, force, p);
  EXPECT_TRUE(res.converged);
  EXPECT_LE(res.residual, opt.tolerance);
  EXPECT_TRUE((p >= 0).all());
  EXPECT_NEAR(p.sum() * grid.cell_area(), force, 1e-12 * force);
  const double fraction = double((p > 0).count()) / grid.size();
  EXPECT_GT(fraction, 0.005);
  EXPECT_LT(fraction, 0.5);
  // The recomputation differs from the solver's own only by the round-off of one more
  // convolution (~1e-15 relative): the same tolerance holds.
  EXPECT_LE(kkt_residual(grid, kSteel, z, p, res.indentation), opt.tolerance);
  RecordProperty("iterations", res.iterations);
  RecordProperty("convolutions", res.convolutions);
  RecordProperty("residual", std::to_string(res.residual));
  RecordProperty("contact_fraction", std::to_string(fraction));

  // Indentation control at the indentation found reproduces the force.
  Field q;
  const NormalResult rd = solver.solve_indentation(z, res.indentation, q);
  EXPECT_LE(rd.residual, opt.tolerance);
  EXPECT_NEAR(rd.force, force, 1e-6 * force);
  RecordProperty("indentation_iterations", rd.iterations);
}

// From cg::kUnverifiedTolerance up a normal solve ends on its incrementally updated image,
// without the verifying product: the rough case's solve at 1e-6 and
// 1e-10 still meets its tolerance when the KKT residual is recomputed from a fresh product
// (kkt_residual), and its reported residual is the recomputed one to the updates' drift (three
// decades below cg::kUnverifiedTolerance). Restarted from its own solution a solve then costs
// the start's image alone (one product), where below the threshold (1e-12) it still confirms
// the residual on a second one.
TEST(NormalSolverRough, EndsWithoutTheVerifyingProductWithinTheTolerance) {
  const RoughCase rough;
  HalfSpace hs(rough.grid, kSteel, Coupling::analogy);
  for (const double tol : {1e-6, 1e-10}) {
    NormalSolver solver(hs, {tol, 2000, Precondition::automatic});
    Field p;
    const NormalResult res = solver.solve_force(rough.z, rough.force, p);
    const double kkt = kkt_residual(rough.grid, kSteel, rough.z, p, res.indentation);
    EXPECT_LE(kkt, tol) << tol;
    EXPECT_NEAR(res.residual, kkt, 1e-3 * cg::kUnverifiedTolerance) << tol;
    Field again = p;
    const NormalResult rerun = solver.solve_force(rough.z, rough.force, again);
    EXPECT_EQ(rerun.iterations, 0) << tol;
    EXPECT_EQ(rerun.convolutions, 1) << tol;
    const std::string at = tol > 1e-8 ? "_1e-6" : "_1e-10";
    RecordProperty("iterations" + at, res.iterations);
    char drift[32];
    std::snprintf(drift, sizeof drift, "%.2e", std::abs(res.residual - kkt));
    RecordProperty("drift" + at, drift);
  }
  NormalSolver tight(hs, {1e-12, 4000, Precondition::automatic});
  Field p;
  tight.solve_force(rough.z, rough.force, p);
  const NormalResult rerun = tight.solve_force(rough.z, rough.force, p);
  EXPECT_EQ(rerun.convolutions, 2);
}

}  // namespace
}  // namespace fretbem
