// Float FFT convolutions (solver.fft_precision = float): the float operator against the
// double one, Hertz solved both ways, and the refusal of tolerances float cannot reach.
//
// Tolerances: float's unit round-off is 6e-8; an FFT's relative error grows like that times a
// slowly rising factor of the transform size (measured by bench_fft_precision: 1e-7 rms,
// 3e-7 largest, from n = 128 to 1024). The operator checks allow 2e-6 (about ten times the
// measured largest error). The solves use tolerance 1e-6 = kFloatFftMinTolerance, where the
// double solve's own error (the tolerance's) dominates the float round-off.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "fretbem/contact/normal_solver.hpp"
#include "fretbem/contact/stiffness.hpp"
#include "fretbem/core/errors.hpp"
#include "fretbem/elastic/half_space.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/history/stepper.hpp"
#include "fretbem/scenario/scenario.hpp"
#include "fretbem/surface/surface.hpp"
#include "support/hertz.hpp"

namespace fretbem {
namespace {

Material material() {
  Material m;
  m.body1 = Body{210e9, 0.3};
  m.mu = 0.5;
  return m;
}

Field random_field(const Grid& g, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Field f(g.nx, g.ny);
  for (Eigen::Index k = 0; k < f.size(); ++k) f(k) = u(rng);
  return f;
}

double rel_max(const Field& a, const Field& ref) {
  return (a - ref).abs().maxCoeff() / ref.abs().maxCoeff();
}

HalfSpace make(const Grid& g, Coupling c, FftPrecision p) {
  return HalfSpace(g, material(), c, FftOptions{1, false, p});
}

TEST(FftPrecision, FloatConvolutionsMatchDoubleToRoundOff) {
  for (const bool periodic : {false, true}) {
    const Grid g = Grid::square(48, 1e-3, periodic);
    HalfSpace hd(g, material(), Coupling::cerruti, FftOptions{1, false, FftPrecision::float64});
    HalfSpace hf(g, material(), Coupling::cerruti, FftOptions{1, false, FftPrecision::float32});
    EXPECT_EQ(hf.precision(), FftPrecision::float32);
    // Kernels are built in double either way: the scalars derived from them agree exactly.
    EXPECT_EQ(hf.normal_self(), hd.normal_self());
    EXPECT_EQ(hf.normal_max_eigenvalue(), hd.normal_max_eigenvalue());
    const Field p = random_field(g, 1), q = random_field(g, 2);
    Field ud, uf, vd, vf;
    hd.normal(p, ud);
    hf.normal(p, uf);
    EXPECT_LT(rel_max(uf, ud), 2e-6) << "normal, periodic " << periodic;
    EXPECT_GT(rel_max(uf, ud), 0.0) << "the float path was not taken";
    hd.tangential(p, q, ud, vd);
    hf.tangential(p, q, uf, vf);
    EXPECT_LT(rel_max(uf, ud), 2e-6) << "Cerruti x, periodic " << periodic;
    EXPECT_LT(rel_max(vf, vd), 2e-6) << "Cerruti y, periodic " << periodic;
    hd.normal_inverse(p, ud);
    hf.normal_inverse(p, uf);
    EXPECT_LT(rel_max(uf, ud), 2e-6) << "preconditioner, periodic " << periodic;
    EXPECT_EQ(hf.convolutions(), hd.convolutions());
  }
}

// Compliances divided by the transform size are ~1e-27 m/Pa for steel on fine grids; the float
// spectrum is stored normalised so that nothing underflows. A range test, not physics: here
// they would be ~1e-40, below float's smallest normal number.
TEST(FftPrecision, NoUnderflowForStiffMaterialsOnFineCells) {
  Material m = material();
  m.body1.E = 1e24;
  const Grid g = Grid::square(64, 1e-9);
  HalfSpace hd(g, m, Coupling::analogy, FftOptions{1, false, FftPrecision::float64});
  HalfSpace hf(g, m, Coupling::analogy, FftOptions{1, false, FftPrecision::float32});
  const Field p = random_field(g, 3).abs() * 1e12;
  Field ud, uf;
  hd.normal(p, ud);
  hf.normal(p, uf);
  EXPECT_LT(rel_max(uf, ud), 2e-6);
}

TEST(FftPrecision, HertzFloatAgreesWithDouble) {
  const Grid g = Grid::square(128, 2.8e-4);
  const Field z = sphere_surface(g, 0.01);
  auto solve = [&](FftPrecision prec, double tol, Field& p) {
    HalfSpace hs(g, material(), Coupling::analogy, FftOptions{1, false, prec});
    NormalSolver ns(hs, NormalOptions{tol, 2000});
    return ns.solve_force(z, 10.0, p);
  };
  Field p_ref, p_d, p_f;
  const NormalResult ref = solve(FftPrecision::float64, 1e-10, p_ref);
  const NormalResult d = solve(FftPrecision::float64, 1e-6, p_d);
  const NormalResult f = solve(FftPrecision::float32, 1e-6, p_f);
  ASSERT_TRUE(f.converged && d.converged);
  EXPECT_LE(f.residual, 1e-6);
  // The approach is an average over the contact: round-off (1e-7) and the 1e-6 residual both
  // shrink in it (measured 3e-8 float, 6e-8 double).
  EXPECT_NEAR(f.indentation / ref.indentation, 1.0, 1e-6);
  // Pressure: the 1e-6 residual allows ~1e-5 relative (measured 2.4e-5 float, 2.8e-5 double
  // against the 1e-10 reference); float must be no worse than double at the same tolerance
  // by more than its round-off.
  const double err_f = std::sqrt((p_f - p_ref).square().sum() / p_ref.square().sum());
  const double err_d = std::sqrt((p_d - p_ref).square().sum() / p_ref.square().sum());
  EXPECT_LT(err_f, 1e-4);
  EXPECT_LT(err_f, 2 * err_d + 1e-6);
  EXPECT_EQ((p_f > 0).count(), (p_ref > 0).count());  // the same contact set
}

TEST(FftPrecision, UnreachableToleranceFailsAtOnce) {
  const Grid g = Grid::square(32, 1e-3);
  HalfSpace hf = make(g, Coupling::analogy, FftPrecision::float32);
  EXPECT_EQ(hf.min_tolerance(), kFloatFftMinTolerance);
  EXPECT_EQ(make(g, Coupling::analogy, FftPrecision::float64).min_tolerance(), 0.0);
  try {
    NormalSolver ns(hf, NormalOptions{1e-8, 5000});
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("normal solver: tolerance 1e-08"), std::string::npos) << msg;
    EXPECT_NE(msg.find("solver.fft_precision = double"), std::string::npos) << msg;
  }
  EXPECT_NO_THROW(NormalSolver(hf, NormalOptions{kFloatFftMinTolerance, 10}));
  TangentialOperator op(hf);
  EXPECT_THROW(StiffnessSolver(op, 1e-9, 100), InputError);
  EXPECT_NO_THROW(StiffnessSolver(op, 1e-6, 100));
  TangentialOptions tight, loose;
  tight.tolerance = 1e-8, loose.tolerance = 1e-6;
  EXPECT_THROW(ProjectedCgSolver(op, tight), InputError);
  EXPECT_THROW(PartitionSolver(op, tight), InputError);
  EXPECT_NO_THROW(ProjectedCgSolver(op, loose));
  EXPECT_NO_THROW(PartitionSolver(op, loose));
}

const std::string kHertz = fretbem_test::kSteelSphere32 + R"(path = ramp
amplitude = 0.8
steps = 2
)";

Scenario parse(const std::vector<std::string>& overrides) {
  return parse_scenario(kHertz, "t.ini", std::filesystem::temp_directory_path(), overrides);
}

TEST(FftPrecision, ScenarioKeyDefaultsAndRefusals) {
  EXPECT_EQ(parse({}).solver.fft_precision, FftPrecision::float64);
  const Scenario f = parse({"solver.fft_precision=float"});
  EXPECT_EQ(f.solver.fft_precision, FftPrecision::float32);
  // No tolerance given: float's floor becomes the default, visible in the resolved scenario.
  EXPECT_EQ(f.solver.tolerance, kFloatFftMinTolerance);
  EXPECT_NE(f.resolved_text.find("fft_precision = float"), std::string::npos);
  EXPECT_EQ(parse_scenario(f.resolved_text, "r.ini", ".").solver.tolerance, kFloatFftMinTolerance);
  EXPECT_EQ(parse({"solver.fft_precision=float", "solver.tolerance=1e-4"}).solver.tolerance, 1e-4);
  auto error = [](const std::vector<std::string>& o) {
    try {
      parse(o);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(error({"solver.fft_precision=float", "solver.tolerance=1e-8"}),
            "--set solver.tolerance=1e-8: below 1e-06, the smallest tolerance float FFTs can "
            "reach (solver.fft_precision = float): raise it or use solver.fft_precision = "
            "double");
  EXPECT_EQ(error({"solver.fft_precision=flaot"}),
            "--set solver.fft_precision=flaot: not one of double|float (did you mean 'float'?)");
  // A Scenario assembled in code skips the parser's check; build_model still refuses it.
  Scenario bad = f;
  bad.solver.tolerance = 1e-9;
  EXPECT_THROW(build_model(bad), InputError);
}

// The whole run path (normal, tangential, stiffness) in float: the same observables as double
// to what the 1e-6 tolerance allows.
TEST(FftPrecision, CattaneoRunFloatMatchesDouble) {
  auto run = [](const std::string& prec) {
    return fretbem_test::run_steps(
        parse({"solver.fft_precision=" + prec, "solver.tolerance=1e-6"}));
  };
  const auto d = run("double"), f = run("float");
  ASSERT_EQ(d.size(), f.size());
  for (std::size_t k = 0; k < d.size(); ++k) {
    EXPECT_EQ(f[k].contact_area, d[k].contact_area) << k;
    if (k == 0) continue;                            // no tangential load yet
    EXPECT_NEAR(f[k].Fx / d[k].Fx, 1.0, 1e-9) << k;  // force control: imposed
    EXPECT_NEAR(f[k].Ux / d[k].Ux, 1.0, 1e-4) << k;
    EXPECT_NEAR(f[k].kx / d[k].kx, 1.0, 1e-4) << k;
  }
}

}  // namespace
}  // namespace fretbem
