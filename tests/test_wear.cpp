// Wear (docs/architecture.md, validation ladder rung 8): bookkeeping of the laws, partial-slip
// shakedown, gross-slip wear, integrators against the cycle-by-cycle reference.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "fretbem/core/format.hpp"
#include "fretbem/elastic/closed_forms.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/history/stepper.hpp"
#include "fretbem/scenario/scenario.hpp"
#include "fretbem/wear/integrator.hpp"
#include "support/temp_dir.hpp"

using namespace fretbem;

namespace {

constexpr double kE = 210e9, kNu = 0.3, kMu = 0.5, kP = 10.0, kR = 0.01, kL = 2.8e-4;

// Hertz sphere at constant normal force kP, sine tangential load.
std::string scenario_text(int n, const std::string& load, const std::string& wear) {
  return "[material]\nE = 210e9\nnu = 0.3\nmu = 0.5\n[grid]\nn = " + std::to_string(n) +
         "\nlength = 2.8e-4\n[surface]\ntype = sphere\nradius = 0.01\n[load]\nnormal_force = 10\n"
         "path = sine\ncycles = 2\nsteps_per_cycle = 4\n" +
         load + "[solver]\nstiffness = false\ntolerance = 1e-9\n[wear]\n" + wear;
}

std::string partial_slip(int n, double k, double N, const std::string& integ, double rtol = 1e-3) {
  char w[256];
  std::snprintf(w, sizeof w,
                "law = archard\ncoefficient = %g\ncycles = %g\nintegrator = %s\n"
                "rtol = %g\natol = 1e-11\n",
                k, N, integ.c_str(), rtol);
  return scenario_text(n, "control = force\namplitude = 0.6\n", w);
}

std::unique_ptr<Model> model_of(const std::string& text) {
  return build_model(parse_scenario(text, "wear_test", std::filesystem::temp_directory_path()));
}

// Snapshots (N, worn depth, pressure) of a run.
struct Snapshots final : Observer {
  std::vector<double> N;
  std::vector<Field> worn, pressure;
  void snapshot(double n, const Field& w, const Field& p, bool) override {
    N.push_back(n), worn.push_back(w), pressure.push_back(p);
  }
};

struct WearRun {
  std::unique_ptr<Model> model;
  WearReport rep;
  Snapshots snaps;
};

WearRun run(const std::string& text) {
  WearRun r;
  r.model = model_of(text);
  Stepper st(*r.model);
  WearCycles cyc(*r.model, st);
  r.rep = integrate_wear(*r.model, cyc, r.snaps);
  return r;
}

// Hertz contact radius a = (3 P R / 4 E*)^(1/3) (Johnson, Contact Mechanics, eq. 4.22).
double hertz_a() {
  return closed_forms::hertz_contact_radius(kP, kR, kE / (1 - kNu * kNu));
}

Field radius(int n) {
  const Grid g = Grid::square(n, kL);
  Field r(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) r(i, j) = std::hypot(g.x(i), g.y(j));
  return r;
}

double masked_max(const Field& f, const Field& mask) {
  return (f * mask).abs().maxCoeff();
}

}  // namespace

// Worn volume = k sum_steps sum_nodes p |s| h^2, with s read back as the growth of the
// accumulated slip vector (independent of the law's code path); energy law: alpha x dissipation.
TEST(WearBookkeeping, ArchardVolumeIsIntegratedLaw) {
  const double k = 1e-13;
  auto m = model_of(partial_slip(48, k, 1, "cycle"));
  Stepper st(*m);
  const double h2 = m->scenario.grid.cell_area();
  double expected = 0.0;
  for (std::size_t s = 0; s < st.steps(); ++s) {
    const VecField slip0 = st.state().slip;
    st.advance(s);
    Field len2 = Field::Zero(slip0[0].rows(), slip0[0].cols());
    for (std::size_t c = 0; c < slip0.size(); ++c) len2 += (st.state().slip[c] - slip0[c]).square();
    expected += k * (st.state().pressure * len2.sqrt()).sum() * h2;
  }
  ASSERT_GT(expected, 0.0);
  EXPECT_NEAR(st.memory().wear_volume / expected, 1.0, 1e-9);
  EXPECT_NEAR(st.state().wear.sum() * h2 / expected, 1.0, 1e-9);
}

TEST(WearBookkeeping, EnergyVolumeIsAlphaTimesDissipation) {
  const double alpha = 2e-13;
  std::string text = partial_slip(48, alpha, 1, "cycle");
  text.replace(text.find("archard"), 7, "energy");
  auto m = model_of(text);
  Stepper st(*m);
  for (std::size_t s = 0; s < st.steps(); ++s) st.advance(s);
  ASSERT_GT(st.memory().dissipation, 0.0);
  EXPECT_NEAR(st.memory().wear_volume / (alpha * st.memory().dissipation), 1.0, 1e-9);
}

// One quadrature of the bound for the dissipation and both wear laws: a slipping node's work is
// its bound along the slip times |s|, and at a constant mu that bound is mu times the pressure
// Archard takes, so every step's (and every node's) Archard worn depth is (k / mu) x its
// dissipation and the energy law's alpha x it, to round-off. Under a normal load that falls
// and rises within steps (trapezoid of the bound, nodes opening within a step), and in cycle
// mode, where each cycle's wear moves the bound at its first step: the end-of-step pressure
// in Archard against the trapezoid in the dissipation put each cycle's worn volume 1.7-2.1e-4
// below (k / mu) x its energy (fretting_wear.ini, n = 128, k = 2e-12).
TEST(WearBookkeeping, BothLawsIntegrateTheDissipationsBound) {
  const fretbem_test::TempDir tmp("wear_quadrature");
  const std::filesystem::path table = tmp / "table.csv";
  std::ofstream(table) << "time,Fz,Fx\n0,10,0\n1,12,2.5\n2,7,-1.5\n3,11,2\n4,6,-1.2\n5,10,0\n"
                          "6,12,2.5\n7,7,-1.5\n";
  for (const char* law : {"archard", "energy"}) {
    const double c = 2e-13, per_joule = std::string(law) == "archard" ? c / kMu : c;
    auto m = model_of(
        "[material]\nE = 210e9\nnu = 0.3\nmu = 0.5\n[grid]\nn = 32\nlength = 2.8e-4\n"
        "[surface]\ntype = sphere\nradius = 0.01\n[load]\npath = table\ntable = " +
        table.string() + "\n[solver]\nstiffness = false\ntolerance = 1e-9\n[wear]\nlaw = " + law +
        "\ncoefficient = 2e-13\ncycles = 1\n");
    Stepper st(*m);
    double worst_step = 0.0;
    for (std::size_t k = 0; k < st.steps(); ++k) {
      const double v0 = st.memory().wear_volume, d0 = st.memory().dissipation;
      st.advance(k);
      const double dv = st.memory().wear_volume - v0, dd = st.memory().dissipation - d0;
      worst_step = std::max(worst_step, std::abs(dv - per_joule * dd) / (per_joule * dd + 1e-300));
    }
    const Field& w = st.state().wear;
    const double worst_node =
        (w - per_joule * st.state().dissipation).abs().maxCoeff() / w.abs().maxCoeff();
    std::printf("[ %s ] worst step %.3g, worst node %.3g (relative)\n", law, worst_step,
                worst_node);
    ASSERT_GT(st.memory().dissipation, 0.0);
    EXPECT_LT(worst_step, 1e-12) << law;
    EXPECT_LT(worst_node, 1e-12) << law;
  }
  // Cycle mode: each cycle's worn volume against its energy.
  auto m = model_of(partial_slip(32, 2e-12, 20, "cycle"));
  Stepper st(*m);
  WearCycles cyc(*m, st);
  Observer silent;
  const WearReport rep = integrate_wear(*m, cyc, silent);
  double worst_cycle = 0.0;
  for (std::size_t i = 1; i < rep.history.size(); ++i) {
    const double dv = rep.history[i].wear_volume - rep.history[i - 1].wear_volume;
    const double expected = 2e-12 / kMu * rep.history[i - 1].energy;
    worst_cycle = std::max(worst_cycle, std::abs(dv / expected - 1.0));
  }
  std::printf("[ cycle mode ] worst cycle %.3g (relative)\n", worst_cycle);
  EXPECT_LT(worst_cycle, 1e-12);
}

TEST(WearBookkeeping, NoWearLawNoWear) {
  std::string text = partial_slip(32, 1e-13, 1, "cycle");
  text = text.substr(0, text.find("[wear]"));
  auto m = model_of(text);
  EXPECT_EQ(m->wear, nullptr);
  Stepper st(*m);
  for (std::size_t s = 0; s < st.steps(); ++s) st.advance(s);
  EXPECT_EQ(st.memory().wear_volume, 0.0);
  EXPECT_EQ(st.state().wear.abs().maxCoeff(), 0.0);
}

// Partial slip at constant P, Q = 0.6 mu P: the stick zone r < c = a (1 - 0.6)^(1/3)
// (Cattaneo–Mindlin) never slips, so it never wears; the annulus c < r < a wears until its
// pressure is gone (shakedown: Ciavarella & Hills 1999; Popov 2014). A margin of 1.5 cells
// around c and a absorbs the staircase of the discrete boundary.
TEST(WearPartialSlip, StickZoneUnwornAnnulusShakesDown) {
  const int n = 48;
  WearRun r = run(partial_slip(n, 2e-12, 4000, "erk"));
  const double a = hertz_a(), c = a * closed_forms::cattaneo_stick_ratio(0.6), h = kL / n;
  const Field rr = radius(n);
  const Field stick = (rr < c - 1.5 * h).cast<double>();
  const Field annulus = (rr > c + h && rr < a - h).cast<double>();
  // Load shed by the annulus moves to the stick zone and the indentation grows, so the contact
  // may reach past a; a node never within reach of the final indentation (r^2 / 2R > delta, the
  // indentation against the unworn datum) never touched and cannot be worn.
  const double delta = r.rep.history.back().delta;
  const Field outside = (rr * rr / (2 * kR) > delta + 2 * h * rr / kR).cast<double>();
  const Field& W = r.rep.worn;
  const double wmax = W.maxCoeff();
  ASSERT_GT(wmax, 0.0);
  EXPECT_LT(masked_max(W, stick), 1e-6 * wmax);
  EXPECT_EQ(masked_max(W, outside), 0.0);
  EXPECT_EQ(((W > 0.0).cast<double>() * annulus).sum(), annulus.sum());  // all worn
  // Stick area at the peak load: unchanged by wear (same discrete set) and near pi c^2.
  const auto& hist = r.rep.history;
  EXPECT_EQ(hist.front().stick_area, hist.back().stick_area);
  EXPECT_NEAR(hist.back().stick_area / (std::numbers::pi * c * c), 1.0, 0.1);
  // Annulus load decreases with N and most of it is gone at the end.
  std::vector<double> load;
  for (const auto& p : r.snaps.pressure) load.push_back((p * annulus).sum());
  for (std::size_t i = 1; i < load.size(); ++i) EXPECT_LE(load[i], load[i - 1] * (1 + 1e-9));
  EXPECT_LT(load.back(), 0.3 * load.front());
  // Wear rate (volume per cycle between snapshots) decays toward zero.
  const double h2 = h * h;
  const auto& N = r.snaps.N;
  const std::size_t m = N.size() - 1;
  const double rate0 = r.snaps.worn[1].sum() * h2 / N[1];
  const double rate_end = (r.snaps.worn[m] - r.snaps.worn[m - 1]).sum() * h2 / (N[m] - N[m - 1]);
  EXPECT_LT(rate_end, 0.2 * rate0);
  std::printf(
      "[ partial slip ] n=%d N=%g: %g simulated cycles (%d evaluations), annulus load "
      "%.3g -> %.3g, rate %.3g -> %.3g m^3/cycle\n",
      n, r.rep.N, r.rep.simulated_cycles, r.rep.rhs_evaluations, load.front(), load.back(), rate0,
      rate_end);
}

// Both ARKODE integrators against the cycle-by-cycle reference after 500 cycles: the same worn
// profile within 2 % of its maximum depth (the reference's first cycle is the virgin quarter
// plus three quarters, 1/500 of the run, well inside), with far fewer simulated cycles. n = 32
// keeps the 501-cycle reference short; the comparison is on one grid, so coarseness does not
// enter.
TEST(WearIntegrators, ArkodeMatchesCycleByCycle) {
  const int n = 32;
  const double k = 2e-12;
  WearRun ref = run(partial_slip(n, k, 500, "cycle"));
  const double wmax = ref.rep.worn.maxCoeff();
  ASSERT_GT(wmax, 0.0);
  // The Jacobian-free Newton–Krylov variant is checked for accuracy only: it needs more
  // simulated cycles than the reference here (docs/wear.md).
  struct Case {
    const char* name;
    const char* integrator;
    bool fewer_cycles;
  };
  for (const Case& cs : {Case{"erk", "erk", true}, Case{"dirk", "dirk", true},
                         Case{"dirk krylov", "dirk\nnewton = krylov", false}}) {
    WearRun r = run(partial_slip(n, k, 500, cs.integrator));
    const double err = (r.rep.worn - ref.rep.worn).abs().maxCoeff() / wmax;
    std::printf(
        "[ integrators ] %s: %g simulated cycles for 500 (reference 501), max profile "
        "difference %.3g of max depth\n",
        cs.name, r.rep.simulated_cycles, err);
    EXPECT_LT(err, 0.02) << cs.name;
    if (cs.fewer_cycles) {
      EXPECT_LT(r.rep.simulated_cycles, 0.5 * 501) << cs.name;
    }
  }
}

// A long run far past the explicit stability cap (1 / (k s K_max) ~ 60 cycles here, against
// N = 20000) into shakedown: the implicit and explicit integrators reach the same profile
// (2 % of its maximum), the implicit one with fewer simulated cycles, the implicit steps
// keep the stick zone unworn (the stiff modes are damped, not amplified), and both end in the
// closed-form shakedown state.
TEST(WearIntegrators, ImplicitLongRunMatchesExplicit) {
  const int n = 32;
  const double k = 2e-12, N = 20000;
  WearRun e = run(partial_slip(n, k, N, "erk"));
  WearRun i = run(partial_slip(n, k, N, "dirk"));
  const double wmax = e.rep.worn.maxCoeff();
  ASSERT_GT(wmax, 0.0);
  const double err = (i.rep.worn - e.rep.worn).abs().maxCoeff() / wmax;
  std::printf(
      "[ long run ] N = %g: erk %g, dirk %g simulated cycles (%ld Newton iterations); profile "
      "difference %.3g of max depth\n",
      N, e.rep.simulated_cycles, i.rep.simulated_cycles, i.rep.newton_iterations, err);
  EXPECT_LT(err, 0.02);
  EXPECT_LT(i.rep.simulated_cycles, e.rep.simulated_cycles);
  const double a = hertz_a(), c = a * closed_forms::cattaneo_stick_ratio(0.6), h = kL / n;
  const Field stick = (radius(n) < c - 1.5 * h).cast<double>();
  EXPECT_LT(masked_max(i.rep.worn, stick), 1e-6 * i.rep.worn.maxCoeff());
  // Shakedown (Popov, Sci. Rep. 4:3749, 2014): the annulus is unloaded, the contact is the
  // stick disc r < c, which does not slip any more, and the indenter is the unworn sphere
  // there. An axisymmetric profile f in contact over a fixed disc c carries
  // P = 2 E* int_0^c (d - g(x)) dx with g(x) = x int_0^x f'(r) / sqrt(x^2 - r^2) dr = x^2 / R
  // (Sneddon 1965; Popov & Hess, MDR), so d = P / (2 E* c) + c^2 / (3 R) against the apex —
  // the unworn datum, the apex being in the stick zone. The discrete stick boundary is within
  // half a cell of c (h / 2c = 8.6 % at n = 32) and |dln d / dln c| = 0.5 here: 2.5 %.
  const double Es = kE / (1 - kNu * kNu);
  const double d_inf = kP / (2 * Es * c) + c * c / (3 * kR);
  for (const WearRun* r : {&e, &i}) {
    const WearCycle& last = r->rep.history.back();
    EXPECT_NEAR(last.delta / d_inf, 1.0, 0.025);
    EXPECT_NEAR(last.contact_radius, c, h);
    EXPECT_LE(last.energy, 1e-6 * r->rep.history.front().energy);
  }
  std::printf(
      "[ shakedown ] delta %.5g (erk), %.5g (dirk) against %.5g; contact radius %.4g vs "
      "c = %.4g m\n",
      e.rep.history.back().delta, i.rep.history.back().delta, d_inf,
      i.rep.history.back().contact_radius, c);
}

// The frozen-slip Newton matrix is solved to the accuracy ARKODE asks of a linear solve (its
// delta, 0.05 of the Newton tolerance), not to a relative residual of 1e-8: on the long run
// above, 12.9 inner CG products per Newton iteration against 30.1, for 238 Newton iterations
// against 216 (the trivial predictor's first iterates, answered without a simulated cycle,
// are counted). Where the inner CG matters (rough_fretting_wear.ini, n = 128, N = 1e5,
// wear.rtol = 1e-2) the run takes the same 50 evaluations either way and 3817 convolutions in
// all against 6205 (docs/wear.md, "Cost").
TEST(WearIntegrators, NewtonSolvesStopAtArkodesLinearTolerance) {
  WearRun r = run(partial_slip(32, 2e-12, 20000, "dirk"));
  ASSERT_GT(r.rep.newton_iterations, 0);
  const double per_newton = double(r.rep.inner_iterations) / double(r.rep.newton_iterations);
  std::printf("[ inner CG ] %ld products, %ld Newton iterations: %.3g per iteration\n",
              r.rep.inner_iterations, r.rep.newton_iterations, per_newton);
  EXPECT_LE(per_newton, 15.0);
  EXPECT_LE(r.rep.newton_iterations, 240);
}

// TR-BDF2's implicit stages start Newton from the step's start (the trivial predictor), the
// state the explicit first stage has just evaluated: the wear map is a function of the worn
// depth alone, so that iterate is answered from the evaluation before it (wear_rhs), never
// simulated twice in a row. Without it every Newton iteration and every step's first stage
// would be a simulated cycle: evaluations >= steps + Newton iterations.
TEST(WearIntegrators, RepeatedIterateIsNotSimulatedAgain) {
  WearRun r = run(partial_slip(32, 2e-12, 20000, "dirk"));
  ASSERT_GT(r.rep.steps, 0);
  for (std::size_t k = 1; k < r.rep.history.size(); ++k)
    EXPECT_FALSE(r.rep.history[k].worn_hash == r.rep.history[k - 1].worn_hash &&
                 r.rep.history[k].N != r.rep.history[k - 1].N)
        << "row " << k << " repeats the worn depth of the row before it";
  EXPECT_LT(r.rep.rhs_evaluations, r.rep.steps + r.rep.newton_iterations);
  std::printf("[ memo ] %d evaluations for %ld steps and %ld Newton iterations\n",
              r.rep.rhs_evaluations, r.rep.steps, r.rep.newton_iterations);
}

// Two tolerances give the same long-run profile (2 % of its maximum).
TEST(WearIntegrators, ToleranceIndependence) {
  const int n = 32;
  WearRun a = run(partial_slip(n, 2e-12, 1500, "erk", 1e-3));
  WearRun b = run(partial_slip(n, 2e-12, 1500, "erk", 1e-4));
  const double wmax = b.rep.worn.maxCoeff();
  EXPECT_LT((a.rep.worn - b.rep.worn).abs().maxCoeff(), 0.02 * wmax);
  std::printf("[ tolerance ] rtol 1e-3: %g, 1e-4: %g simulated cycles\n", a.rep.simulated_cycles,
              b.rep.simulated_cycles);
}

// Tractions carried cycle to cycle with a fast wear (stability number k s K near 0.1 per
// cycle): the stick zone is still never worn — no instability.
TEST(WearIntegrators, CarriedTractionsNeverWearStickZone) {
  const int n = 48;
  WearRun r = run(partial_slip(n, 1e-11, 300, "cycle"));
  const double a = hertz_a(), c = a * closed_forms::cattaneo_stick_ratio(0.6), h = kL / n;
  const Field stick = (radius(n) < c - 1.5 * h).cast<double>();
  const double wmax = r.rep.worn.maxCoeff();
  ASSERT_GT(wmax, 0.0);
  EXPECT_LT(masked_max(r.rep.worn, stick), 1e-6 * wmax);
  EXPECT_EQ(r.rep.history.front().stick_area, r.rep.history.back().stick_area);
}

// Gross slip, displacement amplitude D = 10 um against a full-sliding shift of ~0.2 um: the
// whole contact wears, it widens, the peak pressure falls, and the worn volume grows at
// k P 4 D per cycle. The elastic tangential displacement takes back 4 mu (E*/G*) <u_z>
// <= 4 x 0.5 x 1.21 x 0.38 um per cycle from 4 D = 40 um, i.e. < 2.5 %: inside 5 %.
TEST(WearGrossSlip, WholeContactWearsVolumeLinear) {
  const int n = 64;
  const double k = 1e-15, D = 1e-5;
  char w[200];
  std::snprintf(w, sizeof w,
                "law = archard\ncoefficient = %g\ncycles = 4000\nintegrator = erk\n"
                "rtol = 1e-3\natol = 1e-11\n",
                k);
  char l[100];
  std::snprintf(l, sizeof l, "control = displacement\ndisplacement_amplitude = %g\n", D);
  WearRun r = run(scenario_text(n, l, w));
  const double a = hertz_a(), h = kL / n;
  const Field inside = (radius(n) < a - 1.5 * h).cast<double>();
  const Field& W = r.rep.worn;
  EXPECT_EQ(((W > 0.0).cast<double>() * inside).sum(), inside.sum());  // every node worn
  const auto& hist = r.rep.history;
  EXPECT_GT(hist.back().contact_radius, hist.front().contact_radius + h);
  EXPECT_LT(hist.back().peak_pressure, 0.9 * hist.front().peak_pressure);
  // Slope of V(N) over the second half of the run (least squares over the evaluations).
  double sn = 0, sv = 0, snn = 0, snv = 0, cnt = 0;
  for (const auto& c : hist)
    if (c.N >= 2000)
      sn += c.N, sv += c.wear_volume, snn += c.N * c.N, snv += c.N * c.wear_volume, cnt += 1;
  ASSERT_GE(cnt, 3);
  const double slope = (cnt * snv - sn * sv) / (cnt * snn - sn * sn);
  EXPECT_NEAR(slope / (k * kP * 4 * D), 1.0, 0.05);
  std::printf(
      "[ gross slip ] %g simulated cycles for N = 4000; dV/dN / (k P 4D) = %.4f; "
      "radius %.3g -> %.3g m, peak p %.3g -> %.3g Pa\n",
      r.rep.simulated_cycles, slope / (k * kP * 4 * D), hist.front().contact_radius,
      hist.back().contact_radius, hist.front().peak_pressure, hist.back().peak_pressure);
}

// Without wear.atol the absolute tolerance is rtol x the indentation of the unworn surface:
// the same run as with that value given in metres (the indentation is the first
// row's delta at constant normal force), to the bit.
TEST(WearIntegrators, DefaultAbsoluteToleranceIsRtolTimesIndentation) {
  std::string text = partial_slip(32, 2e-12, 300, "dirk");
  const std::string atol = "atol = 1e-11\n";
  text.erase(text.find(atol), atol.size());
  WearRun a = run(text);
  char given[64];
  std::snprintf(given, sizeof given, "atol = %.17g\n", 1e-3 * a.rep.history.front().delta);
  WearRun b = run(text + given);
  ASSERT_GT(a.rep.worn.maxCoeff(), 0.0);
  EXPECT_EQ((a.rep.worn - b.rep.worn).abs().maxCoeff(), 0.0);
  EXPECT_EQ(a.rep.simulated_cycles, b.rep.simulated_cycles);
}

// A flat in complete contact on a periodic grid has no approach (every node touches at once;
// the periodic kernel's mean mode is free): delta_0 = 0, so rtol x delta_0 is no tolerance and
// ARKODE's error weights 1 / (rtol |W| + atol) on the unworn W = 0 are infinite. The ODE
// integrators refuse it naming wear.atol; with wear.atol given the run goes on, and under a
// uniform tangential load below mu F_z every node carries tau = 0.9 mu p < mu p (uniform
// pressure, uniform traction: the exact periodic solution), slips nowhere and wears nothing.
TEST(WearIntegrators, ZeroIndentationNeedsAGivenAbsoluteTolerance) {
  const std::string flat =
      "[material]\nE = 5e9\nnu = 0.49\nmu = 0.8\n[grid]\nn = 16\nlength = 2.8e-4\n"
      "periodic = true\n[surface]\ntype = flat\n[load]\npath = sine\nnormal_force = 0.5\n"
      "amplitude = 0.9\nsteps_per_cycle = 8\n[wear]\nlaw = archard\ncycles = 200\n"
      "coefficient = 5e-10\nrtol = 0.01\nintegrator = ";
  for (const char* integ : {"erk", "dirk", "arkode"}) {
    SCOPED_TRACE(integ);
    try {
      run(flat + integ + "\n");
      ADD_FAILURE() << "not refused";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("wear.atol"), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
    const WearRun r = run(flat + integ + "\natol = 1e-9\n");
    EXPECT_EQ(r.rep.N, 200.0);
    EXPECT_EQ(r.rep.worn.abs().maxCoeff(), 0.0);
  }
}

// wear.integrator = erk chosen past kImplicitPastCaps stability caps: the run keeps the method
// asked for and warns at its start, naming the cap and the implicit integrators (the sweep's
// erk run to N = 5e4 at n = 32 simulated 6303 cycles, over N/10). Under 50 caps, and for dirk
// or arkode, no warning. The cap is 1 / (k s K_max) of the unworn surface's steady cycle.
TEST(WearIntegrators, ExplicitPastStabilityCapsWarns) {
  struct Warnings final : Observer {
    std::vector<std::string> lines;
    void warn(const std::string& line) override { lines.push_back(line); }
  };
  auto warnings = [](const std::string& text, double* cap) {
    auto model = model_of(text);
    Stepper st(*model);
    WearCycles cyc(*model, st);
    Warnings log;
    integrate_wear(*model, cyc, log, nullptr, 1);  // the first step is enough
    *cap = explicit_step_cap(*model, cyc.steady(0.0, Field::Zero(32, 32)).max_slip);
    return log.lines;
  };
  double cap = 0.0;
  const auto long_erk = warnings(partial_slip(32, 2e-12, 20000, "erk", 1e-2), &cap);
  ASSERT_EQ(long_erk.size(), 1u);
  const std::string& w = long_erk.front();
  std::printf("[ erk warning ] cap %.4g cycles: %s\n", cap, w.c_str());
  EXPECT_GT(20000 / cap, kImplicitPastCaps);
  EXPECT_NE(w.find(format_printf("%.3g", cap)), std::string::npos) << w;
  for (const char* word : {"wear.integrator = erk", "dirk", "arkode"})
    EXPECT_NE(w.find(word), std::string::npos) << word << " in " << w;
  // Under 50 caps (N / cap ~ 33 here) and the integrators that are not capped: silent.
  EXPECT_TRUE(
      warnings(partial_slip(32, 2e-12, 0.66 * kImplicitPastCaps * cap, "erk", 1e-2), &cap).empty());
  EXPECT_TRUE(warnings(partial_slip(32, 2e-12, 20000, "dirk", 1e-2), &cap).empty());
  EXPECT_TRUE(warnings(partial_slip(32, 2e-12, 20000, "arkode", 1e-2), &cap).empty());
}

namespace {

// Products of the rows a WearCycles emits (the measured loop of a steady cycle).
struct ProductCount final : Observer {
  long products = 0;
  void on_step(const StepRecord& r, const InterfaceState&, const Model&) override {
    products += r.convolutions;
  }
};

}  // namespace

// The steady loop of the wear map on the unworn Hertz contact under +-0.6 mu P starts its steps
// from Masing's image of the first turning point A (-tau_A at -Q_A, tau_A back at Q_A), a start
// the solver accepts in one product or finishes in a few iterations; from the previous step's
// end each step is a whole solve (~50 products at n = 64). The loop stays the
// Mindlin–Deresiewicz loop: its energy against Johnson eq. 7.60 within 1 %, the accuracy of
// the Cattaneo shift at a = 20 cells (test_stepper: 1 % at 32 cells).
TEST(WearMap, MasingLoopCostsFewProductsAndIsMindlins) {
  auto m = model_of(partial_slip(64, 1e-13, 100, "arkode"));
  Stepper st(*m);
  ProductCount loop;
  WearCycles cyc(*m, st, {&loop});
  const WearCycle c = cyc.steady(0.0, Field::Zero(64, 64));
  std::printf("[ masing loop ] %ld products\n", loop.products);
  EXPECT_LE(loop.products, 12);
  const Material& mat = m->scenario.material;
  const double delta = closed_forms::hertz_approach(hertz_a(), kR);
  const double ustar = closed_forms::full_sliding_shift(kMu, delta, mat.E_star(), mat.G_star());
  const double W = closed_forms::mindlin_energy_per_cycle(0.6, kMu, kP, ustar);
  std::printf("[ masing loop ] energy / Mindlin - 1 = %+.2e\n", c.energy / W - 1.0);
  EXPECT_NEAR(c.energy / W, 1.0, 0.01);
}

// The normal solve of an evaluation starts from the previous evaluation's pressure, the virgin
// step from the Ciavarella–Jäger superposition whose corrective solve starts from the previous
// evaluation's p*: on an unchanged surface the normal and corrective solves meet their
// stopping rules at once (at most 3 products each, against a cold normal solve's ~30) and the
// superposition meets the tangential one (at most 3: its image and the force shift), so the
// evaluation costs its loop and at most 9 products besides. From another surface's starts the
// map is the cold one within 1e-3 of wear.rtol = 1e-3, so that ARKODE's error control sees a
// function of the worn depth.
TEST(WearMap, WarmStartedMapIsTheColdMap) {
  const std::string text = partial_slip(64, 1e-13, 100, "arkode");
  auto m = model_of(text);
  Stepper st(*m);
  ProductCount loop;
  WearCycles cyc(*m, st, {&loop});
  const HalfSpace& hs = *m->half_space;
  auto c0 = hs.convolutions();
  cyc.initial_indentation();  // a cold normal solve
  const auto cold_normal = long(hs.convolutions() - c0);
  const Field W0 = Field::Zero(64, 64);
  c0 = hs.convolutions();
  const WearCycle first = cyc.steady(0.0, W0);
  const auto first_cost = long(hs.convolutions() - c0);
  c0 = hs.convolutions();
  loop.products = 0;
  cyc.steady(0.0, W0);
  const auto again = long(hs.convolutions() - c0);
  std::printf("[ warm map ] cold normal %ld, first evaluation %ld, again %ld products (loop %ld)\n",
              cold_normal, first_cost, again, loop.products);
  EXPECT_LE(again, loop.products + 9);
  // A worn depth of 5 % of the indentation in the shape of the wear: the warm start comes
  // from the unworn surface's pressure, the cold one from a fresh model.
  const Field W1 = first.rate * (0.05 * first.delta / first.rate.maxCoeff());
  const Field warm = cyc.steady(0.0, W1).rate;
  auto m2 = model_of(text);
  Stepper st2(*m2);
  WearCycles cold(*m2, st2);
  const Field reference = cold.steady(0.0, W1).rate;
  const double rel = (warm - reference).abs().maxCoeff() / reference.abs().maxCoeff();
  std::printf("[ warm map ] max |w_warm - w_cold| / max w = %.3g\n", rel);
  EXPECT_LE(rel, 1e-6);
}

// Evaluations along a straight path W_k = k s (s in the shape of the wear, 1 % of the
// indentation per step): the normal solve of W_3 starts from the path's pressures extrapolated
// to it (WearWarmStart::start_for), which on the contact set the path keeps is the pressure of
// W_3 itself (p is affine in W there), so it costs fewer products than the start from W_2's
// pressure alone; either start gives the cold start's map within 1e-6 of its maximum, far
// inside wear.rtol, as above.
TEST(WearMap, ExtrapolatedStartCutsTheNormalSolve) {
  const std::string text = partial_slip(64, 1e-13, 100, "arkode");
  auto m = model_of(text);
  Stepper st(*m);
  WearCycles path(*m, st);
  const WearCycle first = path.steady(0.0, Field::Zero(64, 64));
  const Field s = first.rate * (0.01 * first.delta / first.rate.maxCoeff());
  path.steady(0.0, s);
  path.steady(0.0, 2.0 * s);
  // Products of the whole evaluation: its corrective solve starts from W_2's p* and its loop
  // from Masing's image either way, so the difference is the normal solve's start.
  const auto start_cost = [](WearCycles& cyc, const HalfSpace& hs, const Field& W, Field& rate) {
    const auto c0 = hs.convolutions();
    rate = cyc.steady(0.0, W).rate;
    return long(hs.convolutions() - c0);
  };
  Field extrapolated, last, cold;
  const long along_path = start_cost(path, *m->half_space, 3.0 * s, extrapolated);
  auto m2 = model_of(text);
  Stepper st2(*m2);
  WearCycles one(*m2, st2);
  one.steady(0.0, 2.0 * s);  // a path of one evaluation: its pressure is the start
  const long from_last = start_cost(one, *m2->half_space, 3.0 * s, last);
  auto m3 = model_of(text);
  Stepper st3(*m3);
  WearCycles fresh(*m3, st3);
  cold = fresh.steady(0.0, 3.0 * s).rate;  // its first evaluation starts cold
  std::printf(
      "[ extrapolated start ] evaluation of W_3: %ld products along the path, %ld from "
      "W_2's pressure\n",
      along_path, from_last);
  EXPECT_LT(along_path, from_last);
  const double scale = cold.abs().maxCoeff();
  const double rel_path = (extrapolated - cold).abs().maxCoeff() / scale;
  const double rel_last = (last - cold).abs().maxCoeff() / scale;
  std::printf("[ extrapolated start ] max |w - w_cold| / max w: %.3g (path), %.3g (last)\n",
              rel_path, rel_last);
  EXPECT_LE(rel_path, 1e-6);
  EXPECT_LE(rel_last, 1e-6);
}
