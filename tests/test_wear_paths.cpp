// Wear on any periodic path: a table holding one period, with a varying normal load,
// and sine paths in any direction of the plane.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "fretbem/core/errors.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/history/stepper.hpp"
#include "fretbem/scenario/scenario.hpp"
#include "fretbem/wear/integrator.hpp"
#include "support/temp_dir.hpp"
#include "support/varying_normal_table.hpp"

using namespace fretbem;
namespace fs = std::filesystem;

namespace {

std::string sphere(int n, const std::string& load, const std::string& wear) {
  return "[material]\nE = 210e9\nnu = 0.3\nmu = 0.5\n[grid]\nn = " + std::to_string(n) +
         "\nlength = 2.8e-4\n[surface]\ntype = sphere\nradius = 0.01\n[load]\n" + load +
         "[solver]\nstiffness = false\ntolerance = 1e-9\n[wear]\n" + wear;
}

fs::path table_file(const std::string& name, const std::string& text) {
  const fs::path f = fretbem_test::process_temp_dir() / (name + ".csv");
  std::ofstream(f) << text;
  return f;
}

WearReport integrate(const std::string& text) {
  auto m = build_model(parse_scenario(text, "wear_path", fs::temp_directory_path()));
  Stepper st(*m);
  WearCycles cyc(*m, st);
  Observer silent;
  return integrate_wear(*m, cyc, silent);
}

// Worn volume of one steady cycle of the unworn surface (the wear map's first evaluation).
double steady_volume(const std::string& text) {
  auto m = build_model(parse_scenario(text, "wear_path", fs::temp_directory_path()));
  Stepper st(*m);
  WearCycles cyc(*m, st);
  cyc.start();
  const WearCycle c = cyc.steady(0.0, Field::Zero(m->scenario.grid.nx, m->scenario.grid.ny));
  return c.rate.sum() * m->scenario.grid.cell_area();
}

}  // namespace

// A table holding one period of the sine's turning points (Fx in N = 0.6 mu F_z) is the sine:
// the same steps at constant normal load, so the same worn depth to round-off.
TEST(WearPaths, TableOfOnePeriodIsTheSine) {
  const fs::path f = table_file("sine", "time,Fx\n0,0\n0.25,3\n0.5,0\n0.75,-3\n1,0\n");
  const std::string wear = "law = archard\ncoefficient = 2e-12\ncycles = 300\nintegrator = dirk\n";
  const WearReport sine = integrate(sphere(
      32, "normal_force = 10\npath = sine\ncontrol = force\namplitude = 0.6\ncycles = 1\n", wear));
  const WearReport table =
      integrate(sphere(32, "normal_force = 10\npath = table\ntable = " + f.string() + "\n", wear));
  fs::remove(f);
  const double wmax = sine.worn.maxCoeff();
  ASSERT_GT(wmax, 0.0);
  EXPECT_LT((sine.worn - table.worn).abs().maxCoeff(), 1e-6 * wmax);
}

// Gross slip with a normal load that changes within the period (10 N on the strokes 0 -> D and
// -D -> 0, 5 N on the stroke D -> -D): the steady cycle wears k sum_strokes P |dU| =
// k (10 D + 5 x 2D + 10 D). The elastic take-up at the reversals is below 2.5 % of the
// strokes at D = 10 um (test_wear.cpp, WholeContactWearsVolumeLinear): 5 %.
TEST(WearPaths, TableWithVaryingNormalLoadGrossSlipRate) {
  const double k = 1e-15, D = 1e-5;
  const fs::path f = table_file("gross",
                                "time,Fz,Ux\n0,10,0\n1,10,1e-5\n2,5,1e-5\n3,5,-1e-5\n"
                                "4,10,-1e-5\n5,10,0\n");
  char w[200];
  std::snprintf(w, sizeof w, "law = archard\ncoefficient = %g\ncycles = 100\n", k);
  const double V = steady_volume(
      sphere(32, "path = table\ncontrol = displacement\ntable = " + f.string() + "\n", w));
  fs::remove(f);
  const double closed = k * (10 * D + 5 * 2 * D + 10 * D);
  std::printf("[ table gross slip ] worn volume per cycle %.4g, closed form %.4g\n", V, closed);
  EXPECT_NEAR(V / closed, 1.0, 0.05);
}

// The sine in the y direction wears the transpose of the sine in x (the square grid and the
// sphere are symmetric under x <-> y): the direction of the path is honoured by the wear map
// and the integrator alike.
TEST(WearPaths, DirectionNinetyIsTheTranspose) {
  const std::string wear = "law = archard\ncoefficient = 2e-12\ncycles = 300\nintegrator = dirk\n";
  auto load = [](int deg) {
    return "normal_force = 10\npath = sine\ncontrol = force\namplitude = 0.6\ncycles = 1\n"
           "direction = " +
           std::to_string(deg) + "\n";
  };
  const WearReport x = integrate(sphere(32, load(0), wear));
  const WearReport y = integrate(sphere(32, load(90), wear));
  const double wmax = x.worn.maxCoeff();
  ASSERT_GT(wmax, 0.0);
  const Field yt = y.worn.transpose();
  std::printf("[ direction ] max |W_90^T - W_0| / max W = %.3g\n",
              (yt - x.worn).abs().maxCoeff() / wmax);
  EXPECT_LT((yt - x.worn).abs().maxCoeff(), 1e-4 * wmax);
}

// A path that is not periodic is refused with a message naming the key.
TEST(WearPaths, RampIsRefused) {
  EXPECT_THROW(integrate(sphere(16, "normal_force = 10\npath = ramp\namplitude = 0.5\n",
                                "law = archard\ncoefficient = 1e-12\ncycles = 10\n")),
               InputError);
}

// A friction coefficient that evolves with the accumulated slip needs the physical history:
// the ODE integrators' steady cycle restarts it, so they refuse it; cycle mode accepts it.
TEST(WearPaths, EvolvingFrictionNeedsCycleMode) {
  const std::string load = "normal_force = 10\npath = sine\ncontrol = force\namplitude = 0.5\n";
  const std::string friction = "[friction]\nlaw = evolving\nmu_final = 0.7\nscale = 1\n";
  for (const char* integrator : {"arkode", "erk", "dirk"}) {
    const std::string wear =
        "law = archard\ncoefficient = 1e-11\ncycles = 10\nintegrator = " + std::string(integrator) +
        "\n";
    try {
      parse_scenario(sphere(16, load, wear) + friction, "wear_path", fs::temp_directory_path());
      ADD_FAILURE() << integrator << " accepted friction.law = evolving";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("friction.law"), std::string::npos) << e.what();
    }
  }
  const WearReport rep = integrate(
      sphere(16, load,
             "law = archard\ncoefficient = 1e-11\ncycles = 10\nintegrator = cycle\n" + friction));
  EXPECT_EQ(rep.N, 10.0);
}

// A short run costs no more than cycle by cycle with any integrator (arkode took 17.4 simulated
// cycles for N = 10 before short runs were simulated cycle by cycle).
TEST(WearPaths, ShortRunCostsAtMostEveryCycle) {
  const std::string load = "normal_force = 10\npath = sine\ncontrol = force\namplitude = 0.6\n";
  for (const char* integrator : {"arkode", "erk", "dirk"})
    for (int N : {1, 10, 20}) {
      const WearReport rep = integrate(
          sphere(32, load,
                 "law = archard\ncoefficient = 1e-11\nrtol = 1e-2\ncycles = " + std::to_string(N) +
                     "\nintegrator = " + integrator + "\n"));
      EXPECT_EQ(rep.N, N);
      EXPECT_LE(rep.simulated_cycles, N + 1.0) << integrator << " N = " << N;
    }
}

// A table whose tangential load leaves one line through zero (2-D motion) has
// history-dependent periodic and shakedown states: the ODE integrators' wear map (the steady
// cycle from a traction-free state) is not the run's (arkode ended at 1.54x the max worn depth
// of cycle mode at n = 32, tools/bench/wear_sweep.py), so they refuse it naming load.table;
// cycle mode runs it. A collinear table (sine's turning points along 30 deg) is accepted.
TEST(WearPaths, TwoDimensionalTableNeedsCycleMode) {
  const fs::path f = table_file("2d", "time,Fx,Fy\n0,0,0\n1,2,1\n2,0,2\n3,-2,1\n4,0,0\n");
  const std::string load = "normal_force = 10\npath = table\ntable = " + f.string() + "\n";
  for (const char* integrator : {"arkode", "erk", "dirk"}) {
    const std::string wear = "law = archard\ncoefficient = 1e-11\ncycles = 100\nintegrator = " +
                             std::string(integrator) + "\n";
    try {
      integrate(sphere(16, load, wear));
      ADD_FAILURE() << integrator << " accepted a 2-D table";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("load.table"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("wear.integrator = cycle"), std::string::npos);
    }
  }
  EXPECT_EQ(
      integrate(
          sphere(16, load, "law = archard\ncoefficient = 1e-11\ncycles = 5\nintegrator = cycle\n"))
          .N,
      5.0);
  const fs::path g = table_file("30deg", "time,Fx,Fy\n0,0,0\n1,2.598,1.5\n2,0,0\n3,-2.598,-1.5\n");
  EXPECT_EQ(integrate(sphere(16, "normal_force = 10\npath = table\ntable = " + g.string() + "\n",
                             "law = archard\ncoefficient = 1e-11\ncycles = 30\n"))
                .N,
            30.0);
  fs::remove(f), fs::remove(g);
}

// Under a varying normal load a row's indentation is the one at the period's end, in every
// mode: the steady cycle (ODE rows) and the carried cycle (cycle mode) of the unworn surface
// give the same delta (the solver tolerance). The steady cycle reported it at its last step,
// the first turning point at F_z = 12 N: 5.32e-7 against 4.70e-7 m at n = 32 (1.6x the max
// worn depth of the sweep's run apart).
TEST(WearPaths, RowIndentationAtThePeriodEnd) {
  const fs::path f = table_file("fz", "time,Fz,Fx\n0,10,0\n1,12,3\n2,8,0\n3,12,-3\n4,10,0\n");
  auto m = build_model(parse_scenario(sphere(16, "path = table\ntable = " + f.string() + "\n",
                                             "law = archard\ncoefficient = 1e-11\ncycles = 100\n"),
                                      "wear_path", fs::temp_directory_path()));
  Stepper st(*m);
  WearCycles cyc(*m, st);
  cyc.start();
  const double carried = cyc.carried(0.0).delta;
  const double steady = cyc.steady(0.0, Field::Zero(16, 16)).delta;
  std::printf("[ period end ] delta carried %.9g, steady %.9g m\n", carried, steady);
  EXPECT_NEAR(steady / carried, 1.0, 1e-8);
  fs::remove(f);
}

// One period F_z 10/12/10/8/10 N, F_x 0/3/0/-2/0 N: the normal load falls while the tangential
// load reverses, so the traction state after the virgin loading is not the periodic one.
std::string varying_normal_table(int n, const std::string& wear, fs::path& f) {
  f = table_file("fz_loop", "time,Fz,Fx\n0,10,0\n0.25,12,3\n0.5,10,0\n0.75,8,-2\n1,10,0\n");
  return sphere(n, "path = table\ntable = " + f.string() + "\n", wear);
}

// The ODE's wear map on the unworn surface is the periodic cycle that cycle mode reaches (its
// second carried period onwards), to the solver's noise. The loop measured right after the
// virgin loading dissipated 6.7 % more and wore 5.9 % more (n = 64); at n = 24 it dissipated
// 6.5 % more and its worn depth was off by 0.14 of the maximum.
TEST(WearPaths, VaryingNormalLoadSteadyCycleIsPeriodic) {
  fs::path f;
  auto m = build_model(parse_scenario(
      varying_normal_table(24, "law = archard\ncoefficient = 5e-13\ncycles = 500\n", f),
      "wear_path", fs::temp_directory_path()));
  Stepper st(*m);
  WearCycles cyc(*m, st);
  cyc.start();
  cyc.carried(0.0);  // the virgin period
  const WearCycle periodic = cyc.carried(1.0);
  const WearCycle steady = cyc.steady(0.0, Field::Zero(24, 24));
  const double wmax = periodic.rate.maxCoeff();
  std::printf("[ varying Fz loop ] energy steady %.6g, carried %.6g J; max |dw| / max w = %.3g\n",
              steady.energy, periodic.energy,
              (steady.rate - periodic.rate).abs().maxCoeff() / wmax);
  ASSERT_GT(wmax, 0.0);
  EXPECT_NEAR(steady.energy / periodic.energy, 1.0, 1e-6);
  EXPECT_LT((steady.rate - periodic.rate).abs().maxCoeff(), 1e-6 * wmax);
  fs::remove(f);
}

// Static/kinetic friction (mu_k = 0.4 where a node slipped in the last step) remembers the
// previous step, so its loop is not closed at once either: the ODE's wear map is the periodic
// cycle of cycle mode (from its third carried period on). Measured right after the virgin
// loading it dissipated 3.3 % less (n = 24); a loop without the period's end settled on
// another periodic state, 30 % more wear (n = 32).
TEST(WearPaths, StaticKineticSteadyCycleIsPeriodic) {
  auto m = build_model(parse_scenario(
      sphere(24, "normal_force = 10\npath = sine\ncontrol = force\namplitude = 0.6\n",
             "law = archard\ncoefficient = 5e-13\ncycles = 500\n") +
          "[friction]\nlaw = static_kinetic\nmu_kinetic = 0.4\n",
      "wear_path", fs::temp_directory_path()));
  Stepper st(*m);
  WearCycles cyc(*m, st);
  cyc.start();
  WearCycle periodic;
  for (int k = 0; k < 4; ++k) periodic = cyc.carried(double(k));
  const WearCycle steady = cyc.steady(0.0, Field::Zero(24, 24));
  const double wmax = periodic.rate.maxCoeff();
  std::printf("[ static/kinetic loop ] energy steady %.6g, carried %.6g J\n", steady.energy,
              periodic.energy);
  ASSERT_GT(wmax, 0.0);
  EXPECT_NEAR(steady.energy / periodic.energy, 1.0, 1e-6);
  EXPECT_LT((steady.rate - periodic.rate).abs().maxCoeff(), 1e-6 * wmax);
}

// That table to N = 500 (n = 24, Archard 5e-13, rtol 1e-3): arkode ends where cycle mode does,
// within the ODE tolerance (measured: worn volume +2.4e-4, max depth -4.1e-4; the ODE's wear
// map from the first loop after the virgin loading ended +5.6 % and +0.55 %). The ODE starts
// in the periodic cycle where cycle mode's first period is the virgin one, which wears ~0.6
// of a periodic cycle: 1e-3 of the volume at N = 500 at most, inside the tolerance.
TEST(WearPaths, VaryingNormalLoadOdeMatchesCycleMode) {
  auto run = [](const char* integrator) {
    fs::path f;
    const WearReport r = integrate(varying_normal_table(
        24,
        "law = archard\ncoefficient = 5e-13\ncycles = 500\nrtol = 1e-3\nintegrator = " +
            std::string(integrator) + "\n",
        f));
    fs::remove(f);
    return r;
  };
  const WearReport ode = run("arkode"), cycle = run("cycle");
  const double v_ode = ode.worn.sum(), v_cycle = cycle.worn.sum();
  const double d_ode = ode.worn.maxCoeff(), d_cycle = cycle.worn.maxCoeff();
  std::printf("[ varying Fz wear ] arkode/cycle - 1: volume %.3g, max depth %.3g (%g simulated)\n",
              v_ode / v_cycle - 1.0, d_ode / d_cycle - 1.0, ode.simulated_cycles);
  EXPECT_NEAR(v_ode / v_cycle, 1.0, 1e-3);
  EXPECT_NEAR(d_ode / d_cycle, 1.0, 1e-3);
}

// A rough surface (midpoint, H = 0.3, n = 16) under F_z +-30 % (a 12-row table), Cerruti
// coupling, Archard, dirk with Krylov Newton: the steady cycle settles over 54/13 = 4.15 cycles
// and a TR-BDF2 step costs 6-8 wear-map evaluations, so no step covers twice its cost inside
// the first snapshot intervals (N = 1, 2, 5, 10, 20, 50). After a step that did not pay, the
// cost guard simulates cycle by cycle every interval shorter than twice its cost; a stretch
// after an unpaid step runs on through the snapshots it reaches, starts at no less than
// kMinStretch = 8 cycles and the failed step's cost, and at least doubles while no step pays,
// so after the first step k more follow only once 8 (2^k - 1) cycles fit in N:
// k <= log2(N / 8 + 1). Every step but the last costs at most the cycles one by one after it,
// so the run simulates at most about twice the N + 1 cycles of cycle mode. Measured (`fretbem
// run` of this scenario): 421.7 simulated cycles in 9 steps when each snapshot ended the
// stretch and every interval retried the integrator, 155.3 in 1 step now. The final max worn
// depth is cycle mode's within one cycle's wear of it, 1/N: the ODE's map is the periodic
// cycle, where cycle mode's first period is the virgin loading (measured +3.1e-3 and +4.2e-3).
TEST(WearPaths, CostlyStepsAcrossSnapshotsCostAtMostTwiceEveryCycle) {
  const fs::path f = table_file("fz30", fretbem_test::kTwelveRowVaryingTable);
  const double N = 100;
  auto rough = [&](const char* integrator) {
    return "[material]\nE = 5e9\nnu = 0.25\nmu = 0.5\n[grid]\nn = 16\nlength = 2.8e-4\n"
           "[surface]\ntype = rough\nmethod = midpoint\nhurst = 0.3\nseed = 224\n"
           "rms_slope = 0.02\n[load]\npath = table\ncontrol = force\ntable = " +
           f.string() +
           "\n[solver]\ntolerance = 1e-8\ncoupling = cerruti\n[wear]\nlaw = archard\n"
           "coefficient = 8.0357e-11\nrtol = 1e-3\nnewton = krylov\nindenter_share = 0.5\n"
           "cycles = 100\nintegrator = " +
           std::string(integrator) + "\n";
  };
  const WearReport ode = integrate(rough("dirk")), cycle = integrate(rough("cycle"));
  std::printf("[ costly steps ] %g simulated cycles in %ld steps, %ld stretches for N = %g\n",
              ode.simulated_cycles, ode.steps, ode.stretches, N);
  EXPECT_EQ(ode.N, N);
  EXPECT_LE(double(ode.steps), 1.0 + std::log2(N / 8.0 + 1.0));
  EXPECT_LE(ode.simulated_cycles, 2.0 * (N + 1.0));
  EXPECT_NEAR(ode.worn.maxCoeff() / cycle.worn.maxCoeff(), 1.0, 1.0 / N);
  fs::remove(f);
}

// Gross slip with a short stability cap (D = 10 um, k = 1e-13: cap ~2.8 cycles at n = 64):
// an explicit step of two wear-map evaluations never covers twice its cost, so arkode runs
// the implicit method (61.2 simulated cycles); erk's cost guard stretches, broken by a wasted
// step per snapshot interval, took 117.6 for N = 100 (tools/bench/wear_sweep.py). n = 32
// (cap ~5.6) does not reproduce it.
TEST(WearPaths, ShortCapGrossSlipCostsAtMostEveryCycle) {
  const double N = 100;
  const WearReport rep = integrate(sphere(
      64,
      "normal_force = 10\npath = sine\ncontrol = displacement\ndisplacement_amplitude = 1e-5\n"
      "steps_per_cycle = 4\n",
      "law = archard\ncoefficient = 1e-13\ncycles = 100\nrtol = 1e-2\n"));
  std::printf("[ short cap ] %g simulated cycles for N = %g (implicit %d)\n", rep.simulated_cycles,
              N, int(rep.implicit));
  EXPECT_TRUE(rep.implicit);
  EXPECT_LE(rep.simulated_cycles, N + 1.25);
  EXPECT_TRUE(runs_implicit(WearIntegrator::arkode, 100, 4.9, 1.25));
  EXPECT_FALSE(runs_implicit(WearIntegrator::arkode, 100, 5.1, 1.25));
  EXPECT_FALSE(runs_implicit(WearIntegrator::erk, 1e6, 1.0, 1.25));
  EXPECT_TRUE(runs_implicit(WearIntegrator::arkode, 1e4, 199, 1.25));
}

// Gross slip on a sphere (E = 70 GPa, nu = 0, F_z = 3.2 N, D = 3 um, n = 16) where one cycle
// wears past the stability of a one-cycle step: at k = 1e-10 1/Pa the explicit cap of the
// unworn surface is 0.126 cycles (k s_max K_max = 7.9 > 2), so cycle-by-cycle wear overshoots
// node by node; the ODE integrators ended 11-12 % below `cycle` there (sweep seed 1 case 155)
// and are refused, naming wear.integrator. At k = 2e-11 (cap 0.63) erk runs and agrees with
// `cycle` within its error control, 10 (rtol W + atol) with atol = rtol x the indentation.
TEST(WearPaths, WearPastOneCycleStabilityNeedsCycleMode) {
  auto scenario = [](double k, const char* integrator) {
    char w[160];
    std::snprintf(w, sizeof w, "law = archard\ncoefficient = %g\ncycles = 30\nintegrator = %s\n", k,
                  integrator);
    return "[material]\nE = 70e9\nnu = 0\nmu = 0.3\n[grid]\nn = 16\nlength = 2.8e-4\n"
           "allow_edge_contact = true\n[surface]\ntype = sphere\nradius = 0.01\n[load]\n"
           "path = sine\ncontrol = displacement\nnormal_force = 3.2\n"
           "displacement_amplitude = 3e-6\n[solver]\nstiffness = false\ntolerance = 1e-9\n"
           "[wear]\n" +
           std::string(w);
  };
  for (const char* ode : {"erk", "dirk", "arkode"}) {
    try {
      integrate(scenario(1e-10, ode));
      ADD_FAILURE() << ode << " ran where one cycle wears past a one-cycle step's stability";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("wear.integrator"), std::string::npos) << what;
      EXPECT_NE(what.find("wear.integrator = cycle"), std::string::npos) << what;
    }
  }
  EXPECT_NO_THROW(integrate(scenario(1e-10, "cycle")));
  const WearReport erk = integrate(scenario(2e-11, "erk"));
  const WearReport cycle = integrate(scenario(2e-11, "cycle"));
  const double W = cycle.worn.maxCoeff(), rtol = 1e-3, delta0 = 4.9e-7;  // Hertz delta
  std::printf("[ cap 0.63 ] erk %.6g, cycle %.6g m\n", erk.worn.maxCoeff(), W);
  EXPECT_FALSE(erk.cycle_by_cycle);
  EXPECT_NEAR(erk.worn.maxCoeff(), W, 10.0 * (rtol * W + rtol * delta0));
}

// The threshold itself: ODE runs need a cap of at least kMinOdeCap cycles; `cycle` and runs
// short enough to be simulated cycle by cycle anyway need none.
TEST(WearPaths, OdeCapThreshold) {
  WearSpec w;
  w.cycles = 200;
  w.integrator = WearIntegrator::dirk;
  EXPECT_THROW(require_ode_cap(w, 0.49), InputError);
  EXPECT_NO_THROW(require_ode_cap(w, kMinOdeCap));
  w.integrator = WearIntegrator::cycle;
  EXPECT_NO_THROW(require_ode_cap(w, 0.01));
  w.integrator = WearIntegrator::erk;
  w.cycles = kShortRun;
  EXPECT_NO_THROW(require_ode_cap(w, 0.01));
}

// The Ciavarella–Jäger shortcut (solver.monotone = shortcut) holds on the path's first
// monotone segment from rest only; a wear cycle's steps, reversals included, are solved
// incrementally, so a carried cycle dissipates what it does without the shortcut (to the
// solver tolerance). Taken on every step of a carried cycle, it dissipated 25 % less than
// the closed loop and the ODE integrators ended 32 % above `cycle` (sweep seed 1 case 282).
TEST(WearPaths, ShortcutLeavesWearCyclesIncremental) {
  auto cycles = [](const char* monotone) {
    std::string text =
        sphere(16, "normal_force = 10\npath = sine\ncontrol = force\namplitude = 0.6\ncycles = 1\n",
               "law = archard\ncoefficient = 1e-13\ncycles = 3\nintegrator = cycle\n");
    text.replace(text.find("[solver]\n"), 9,
                 std::string("[solver]\nmonotone = ") + monotone + "\n");
    return integrate(text);
  };
  const WearReport fast = cycles("shortcut"), plain = cycles("incremental");
  ASSERT_EQ(fast.history.size(), plain.history.size());
  for (std::size_t i = 1; i < fast.history.size(); ++i)
    EXPECT_NEAR(fast.history[i].energy, plain.history[i].energy, 1e-6 * plain.history[i].energy)
        << "cycle " << i;
}
