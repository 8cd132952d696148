// Load histories: Mindlin–Deresiewicz loops, energy balance, steady state, paths, resume.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <optional>
#include <sstream>
#include <thread>

#include "fretbem/history/resolution.hpp"
#include "fretbem/io/checkpoint.hpp"
#include "support/child_process.hpp"
#include "support/hertz.hpp"
#include "support/temp_dir.hpp"
#include "support/varying_normal_table.hpp"

using namespace fretbem;
namespace fs = std::filesystem;

namespace {

// Hertz sphere, unit domain, contact radius a = 1/4 at P = 4/3 E* a^3 / R (R = 1).
std::string sphere_scenario(int n, const std::string& load, const std::string& extra = "") {
  return fretbem_test::unit_sphere_ini(n, load, "[solver]\ntolerance = 1e-10\n" + extra);
}

double hertz_force(double E_star) {
  return closed_forms::hertz_force(0.25, 1.0, E_star);
}

struct Recorder : Observer {
  std::vector<StepRecord> rows;
  double max_violation = 0.0;
  bool finite = true;
  void on_step(const StepRecord& r, const InterfaceState& s, const Model& m) override {
    rows.push_back(r);
    Field mag = s.traction[0].square();
    for (std::size_t c = 1; c < s.traction.size(); ++c) mag += s.traction[c].square();
    const Field g = m.scenario.material.mu * s.pressure;
    max_violation = std::max(max_violation, (mag.sqrt() - g).maxCoeff() / g.maxCoeff());
    for (const auto& t : s.traction) finite &= t.allFinite();
  }
};

Recorder run(const std::string& text) {
  return fretbem_test::run_recorded<Recorder>(text);
}

using fretbem_test::cycle_energy;
using fretbem_test::CycleEnergy;

// Mindlin–Deresiewicz (Johnson, Contact Mechanics §7.4–7.5) for the Hertz sphere with
// u* = mu delta E*/G*: initial loading f(Q) = u* (1 - (1 - Q/muP)^(2/3)); Masing branches;
// energy per cycle W = (24/5) mu P u* [1 - (1-q)^(5/3) - (5q/6)(1 + (1-q)^(2/3))].
struct Mindlin {
  double muP, ustar;
  double f(double Q) const { return ustar * closed_forms::cattaneo_shift_ratio(Q / muP); }
  double unload(double Qa, double Q) const { return f(Qa) - 2 * f((Qa - Q) / 2); }
  double reload(double Qa, double Q) const { return -f(Qa) + 2 * f((Qa + Q) / 2); }
  double energy(double q) const {
    return fretbem::closed_forms::mindlin_energy_per_cycle(q, 1.0, muP, ustar);
  }
};

Mindlin mindlin() {
  Material m;
  m.body1 = {1.0, 0.3};
  const double delta = closed_forms::hertz_approach(0.25, 1.0);
  return {0.5 * hertz_force(m.E_star()),
          closed_forms::full_sliding_shift(0.5, delta, m.E_star(), m.G_star())};
}

std::string sine_load(double q, int cycles, int spc) {
  std::ostringstream s;
  s << "normal_force = " << std::setprecision(17) << hertz_force(1.0 / (1 - 0.09))
    << "\npath = sine\ncontrol = force\namplitude = " << q << "\ncycles = " << cycles
    << "\nsteps_per_cycle = " << spc;
  return s.str();
}

}  // namespace

// n = 128, a = L/4 (32 cells): the tangential shift of Cattaneo–Mindlin is reproduced to
// ~3e-4 at this grid (test_tangential), so 1 % on the energy and the branches has margin.
TEST(MindlinDeresiewicz, EnergyPerCycleAndLoopBranches) {
  const Mindlin md = mindlin();
  for (double q : {0.3, 0.8}) {
    const Recorder r = run(sphere_scenario(128, sine_load(q, 2, 64)));
    ASSERT_TRUE(r.finite);
    const CycleEnergy e = cycle_energy(r.rows, 1);
    const double W = md.energy(q);
    std::printf("q* = %.1f: W nodal / closed form - 1 = %+.2e, loop area / nodal - 1 = %+.2e\n", q,
                e.nodal / W - 1, e.loop / e.nodal - 1);
    EXPECT_NEAR(e.nodal / W, 1.0, 0.01);
    const double Qa = q * md.muP;
    double worst = 0.0;
    for (std::size_t k = 1; k < r.rows.size(); ++k) {
      const auto& s = r.rows[k];
      if (s.time <= 1.0 + 1e-12) continue;  // second cycle: the steady loop
      const bool down = s.Fx < r.rows[k - 1].Fx;
      const double U = down ? md.unload(Qa, s.Fx) : md.reload(Qa, s.Fx);
      worst = std::max(worst, std::abs(s.Ux - U) / md.ustar);
    }
    std::printf("q* = %.1f: max |Ux - Masing branch| / u* = %.2e\n", q, worst);
    EXPECT_LT(worst, 0.01);
  }
}

// Energy balance: the F-U loop area (trapezoid) equals the nodal dissipation within 0.5 % at
// 64 steps per cycle, and the difference falls as the steps get finer (trapezoid, O(dt^2)).
TEST(EnergyBalance, LoopAreaEqualsNodalDissipation) {
  double previous = 1.0;
  for (int spc : {64, 128}) {
    const Recorder r = run(sphere_scenario(64, sine_load(0.6, 2, spc)));
    const CycleEnergy e = cycle_energy(r.rows, 1);
    const double diff = std::abs(e.loop / e.nodal - 1);
    std::printf("steps/cycle %d: |loop/nodal - 1| = %.2e\n", spc, diff);
    EXPECT_LT(diff, 0.005);
    EXPECT_LT(diff, previous);
    previous = diff;
  }
}

// At constant normal load the loop is steady from the second cycle on.
TEST(SteadyState, SecondAndThirdCyclesCoincide) {
  const Recorder r = run(sphere_scenario(64, sine_load(0.6, 3, 32)));
  const std::size_t per = 32;
  const double Fs = r.rows[8].Fx, Us = std::abs(r.rows[8].Ux);
  for (std::size_t k = 1; k <= per; ++k) {
    const auto& a = r.rows[per + k];
    const auto& b = r.rows[2 * per + k];
    EXPECT_NEAR(a.Fx, b.Fx, 1e-6 * Fs);
    EXPECT_NEAR(a.Ux, b.Ux, 1e-6 * Us);
  }
  EXPECT_NEAR(cycle_energy(r.rows, 1).nodal, cycle_energy(r.rows, 2).nodal,
              1e-6 * cycle_energy(r.rows, 1).nodal);
}

// solver.monotone = shortcut (Ciavarella–Jäger) gives the incremental ramp's rows.
TEST(Paths, MonotoneShortcutEqualsIncrementalRamp) {
  for (const char* control : {"control = force\namplitude = 0.9",
                              "control = displacement\n"
                              "displacement_amplitude = 0.02"}) {
    const std::string load =
        std::string("normal_force = 0.015\npath = ramp\nsteps = 6\n") + control;
    // Both at solver.tolerance = 1e-10: rows agree to ~1e-8 relative.
    const Recorder inc = run(sphere_scenario(48, load));
    const Recorder cj = run(sphere_scenario(48, load, "monotone = shortcut\n"));
    for (std::size_t k = 0; k < inc.rows.size(); ++k) {
      EXPECT_NEAR(cj.rows[k].Fx, inc.rows[k].Fx, 1e-7 * std::abs(inc.rows.back().Fx));
      EXPECT_NEAR(cj.rows[k].Ux, inc.rows[k].Ux, 1e-7 * std::abs(inc.rows.back().Ux));
      EXPECT_EQ(cj.rows[k].stick_area, inc.rows[k].stick_area);
      EXPECT_NEAR(cj.rows[k].dissipation, inc.rows[k].dissipation,
                  1e-6 * inc.rows.back().dissipation);
    }
  }
}

// The shortcut's corrective solve starts on the secant through the last two rows' p*,
// extrapolated by the ratio of the load increments: on a stick set that holds over the three
// rows p* is linear in the load, so the start is off by the two rows' own solve errors only,
// (1 + 2r) tol at most (r = 1 here): one CG step and the confirming pass (cg::run counts it as
// an iteration); the previous p* alone is a load step of 1e-6 away, 10^4 tolerances, and
// needs several CG steps (8 here). No product
// beyond the corrective solve's own (its start, one per CG step, the confirmation:
// iterations + 1): the shear displacement is (E*/G*) mu K (p - p*) from the two normal
// displacements at hand.
TEST(Paths, ShortcutSecantStartOnAHeldStickSet) {
  const fs::path table = fretbem_test::process_temp_dir() / "held_stick_set.csv";
  {
    std::ofstream t(table);
    t << std::setprecision(17) << "time,Fz,Fx,Fy\n0,0.015,0,0\n";
    for (int k = 1; k <= 4; ++k) t << k << ",0.015," << 0.00375 * (1 + 1e-6 * (k - 1)) << ",0\n";
  }
  const std::string load = "path = table\ntable = " + table.string();
  const Recorder r = run(sphere_scenario(48, load, "monotone = shortcut\nstiffness = none\n"));
  fs::remove(table);
  ASSERT_EQ(r.rows.size(), 5u);
  for (std::size_t k = 2; k < r.rows.size(); ++k) {
    ASSERT_EQ(r.rows[k].stick_area, r.rows[1].stick_area) << k;
    EXPECT_EQ(r.rows[k].convolutions, r.rows[k].tangential_iterations + 1) << k;
    if (k >= 3) {
      EXPECT_LE(r.rows[k].tangential_iterations, 2) << k;
    }
  }
}

// The shortcut's corrective solve starts along the loading curve's tangent at the last row,
// p*_1 - psi_1 dU / mu, where that row solved k_x (psi_1 its solution), else along the secant
// through the last two rows (from p*_1 alone on row 1). On the paper's rough surface (n = 64,
// H = 0.5, a 20-row ramp to full sliding) the stick islands lose nodes every row and the
// tangent at the last row's own set is the closer start: fewer corrective iterations over the
// rows, under displacement and force control. Either start ends within the solver tolerance
// (1e-8) of the corrective solution: Fx and Ux within 1e-8 of their largest values.
TEST(Paths, ShortcutTangentStartCutsTheCorrectiveIterations) {
  for (const bool force : {false, true}) {
    std::ostringstream ini;
    ini << "[material]\nE = 210e9\nnu = 0.3\nmu = 0.5\n[grid]\nn = 64\nlength = 1e-3\n"
        << "[surface]\ntype = rough\nmethod = midpoint\nhurst = 0.5\nrms_slope = 0.05\nseed = 1\n"
        << "[load]\nnormal_force = 300\npath = ramp\nsteps = 20\n"
        << (force ? "control = force\namplitude = 0.9\n"
                  : "control = displacement\ndisplacement_amplitude = 5e-6\n")
        << "[solver]\ntolerance = 1e-8\nmonotone = shortcut\n";
    const Recorder tangent = run(ini.str());
    const Recorder secant = run(ini.str() + "stiffness = turning\n");
    ASSERT_EQ(tangent.rows.size(), secant.rows.size());
    int it_tangent = 0, it_secant = 0;
    double F = 0.0, U = 0.0, worst = 0.0;
    for (const StepRecord& r : secant.rows)
      F = std::max(F, std::abs(r.Fx)), U = std::max(U, std::abs(r.Ux));
    for (std::size_t k = 1; k < tangent.rows.size(); ++k) {
      const StepRecord &a = tangent.rows[k], &b = secant.rows[k];
      EXPECT_NEAR(a.Fx, b.Fx, 1e-8 * F) << k;
      EXPECT_NEAR(a.Ux, b.Ux, 1e-8 * U) << k;
      worst = std::max({worst, std::abs(a.Fx - b.Fx) / F, std::abs(a.Ux - b.Ux) / U});
      it_tangent += a.tangential_iterations, it_secant += b.tangential_iterations;
    }
    std::printf(
        "%s control: corrective iterations from the tangent %d, the secant %d; worst %.1e\n",
        force ? "force" : "displacement", it_tangent, it_secant, worst);
    EXPECT_LT(it_tangent, it_secant);
  }
}

// The shortcut with its starts (tangent and secant) against Cattaneo (Johnson eqs. 7.41-7.42) under
// a displacement ramp: U/U* = 1 - (1 - q)^(2/3) and k_x = dQ/dU = (3/2) (mu P / U*) (1 - q)^(1/3)
// at q = Q/(mu P). The discretisation error falls at least at first order in the cell size
// (n = 32 -> 64 halves it or better) and at n = 64 is below h / (2a) = 1/32 (half a cell of
// the contact radius a = 16 cells).
TEST(Paths, ShortcutRampFollowsCattaneo) {
  const Material m = [] {
    Material x;
    x.body1 = {1.0, 0.3};
    return x;
  }();
  const double P = hertz_force(m.E_star()), muP = 0.5 * P;
  const double ustar = fretbem_test::unit_full_sliding_shift(0.5);
  std::ostringstream load;
  load << std::setprecision(17) << "normal_force = " << P
       << "\npath = ramp\ncontrol = displacement\ndisplacement_amplitude = " << 0.8 * ustar
       << "\nsteps = 4";
  double previous = 2.0;
  for (int n : {32, 64}) {
    const Recorder r = run(sphere_scenario(n, load.str(), "monotone = shortcut\n"));
    double worst = 0.0;
    for (std::size_t k = 1; k < r.rows.size(); ++k) {
      const double q = closed_forms::cattaneo_force_ratio(r.rows[k].Ux / ustar);
      const double kx = 1.5 * muP / ustar * std::cbrt(1 - q);
      worst = std::max(worst, std::abs(r.rows[k].Fx / muP - q));
      worst = std::max(worst, std::abs(r.rows[k].kx / kx - 1));
    }
    std::printf("n = %d: worst |Fx/muP - q|, |kx/kx_Cattaneo - 1| = %.3e\n", n, worst);
    EXPECT_LT(worst, 0.5 * previous);
    previous = worst;
  }
  EXPECT_LT(previous, 1.0 / 32);
}

// Direction angles: a ramp at 30 degrees gives the x ramp rotated (analogy, isotropic).
TEST(Paths, DirectionAngleRotatesTheResponse) {
  const std::string load =
      "normal_force = 0.015\npath = ramp\ncontrol = force\namplitude = 0.7"
      "\nsteps = 5";
  const Recorder rx = run(sphere_scenario(48, load));
  const Recorder r30 = run(sphere_scenario(48, load + "\ndirection = 30"));
  const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
  for (std::size_t k = 0; k < rx.rows.size(); ++k) {
    EXPECT_NEAR(r30.rows[k].Fx, c * rx.rows[k].Fx, 1e-9 * std::abs(rx.rows.back().Fx));
    EXPECT_NEAR(r30.rows[k].Fy, s * rx.rows[k].Fx, 1e-9 * std::abs(rx.rows.back().Fx));
    EXPECT_NEAR(r30.rows[k].Uy, s * rx.rows[k].Ux, 1e-7 * std::abs(rx.rows.back().Ux));
    EXPECT_NEAR(r30.rows[k].stick_area, rx.rows[k].stick_area, 1e-12);
  }
  EXPECT_LT(r30.max_violation, 1e-12);
}

// A table with a varying normal force and a two-dimensional tangential path (full 2-D
// solver) runs, respects |tau| <= mu p and hits every row.
TEST(Paths, TableWithVaryingNormalLoadAndTwoDimensionalPath) {
  const fs::path table = fretbem_test::process_temp_dir() / "table.csv";
  std::ofstream(table) << "time,Fz,Fx,Fy\n0,0.015,0,0\n1,0.02,0.003,0\n2,0.02,0.003,0.003\n"
                          "3,0.012,-0.002,0.001\n4,0.012,0,0\n";
  const Recorder r = run(sphere_scenario(48, "path = table\ntable = " + table.string()));
  ASSERT_EQ(r.rows.size(), 5u);
  EXPECT_TRUE(r.finite);
  EXPECT_LT(r.max_violation, 1e-12);
  EXPECT_NEAR(r.rows[2].Fy, 0.003, 1e-12);
  EXPECT_NEAR(r.rows[3].Fx, -0.002, 1e-12);
  EXPECT_NEAR(r.rows[3].Fz, 0.012, 1e-12);
  EXPECT_GT(r.rows[1].normal_iterations, 0);
  EXPECT_EQ(r.rows[2].normal_iterations, 0);  // same normal load: no re-solve
  fs::remove(table);
}

namespace {

std::vector<std::vector<std::string>> read_csv(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> row;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) row.push_back(c);
    rows.push_back(row);
  }
  return rows;
}

int sh(const std::string& cmd) {
  return std::system((cmd + " > /dev/null 2>&1").c_str());
}

// Same rows; kx (stiffness solve warm start) and solver counts may differ within tolerance.
void expect_same_run(const fs::path& a, const fs::path& b) {
  const auto ra = read_csv(a / "timeseries.csv"), rb = read_csv(b / "timeseries.csv");
  ASSERT_EQ(ra.size(), rb.size());
  const auto& cols = ra[0];
  for (std::size_t i = 1; i < ra.size(); ++i)
    for (std::size_t c = 0; c < cols.size(); ++c) {
      if (cols[c] == "convolutions") continue;
      if (cols[c] == "kx") {
        EXPECT_NEAR(std::stod(ra[i][c]), std::stod(rb[i][c]), 1e-8 * std::stod(ra[i][c]));
        continue;
      }
      EXPECT_EQ(ra[i][c], rb[i][c]) << "row " << i << " column " << cols[c];
    }
  EXPECT_EQ(read_csv(a / "cycles.csv").size(), read_csv(b / "cycles.csv").size());
}

fs::path scenario_file(const std::string& name, const std::string& text) {
  const fs::path dir = fretbem_test::process_temp_dir().fresh(name);
  std::ofstream(dir / "s.ini") << text;
  return dir;
}

}  // namespace

// --stop-after then --resume equals the uninterrupted run.
TEST(Resume, StopAndResumeMatchesUninterruptedRun) {
  const fs::path d = scenario_file("resume", sphere_scenario(48, sine_load(0.6, 2, 16)));
  const std::string bin = FRETBEM_BINARY;
  ASSERT_EQ(sh(bin + " run " + (d / "s.ini").string() + " --quiet --out " + (d / "full").string()),
            0);
  ASSERT_EQ(sh(bin + " run " + (d / "s.ini").string() + " --quiet --stop-after 11 --out " +
               (d / "part").string()),
            0);
  EXPECT_EQ(read_csv(d / "part" / "timeseries.csv").size(), 12u);
  ASSERT_EQ(sh(bin + " run --quiet --resume " + (d / "part").string()), 0);
  expect_same_run(d / "full", d / "part");
  fs::remove_all(d);
}

// Stepper::memory holds what the next step reads besides the InterfaceState: with static_kinetic
// friction under a varying normal load the bound a step ends with depends on the state at its
// start, and a stepper restored after step 6 continues with the uninterrupted run's rows,
// dissipation included (Coulomb work sum g |s|, which takes the bound of the last step).
TEST(Resume, RestoredStepperContinuesWithTheSameDissipation) {
  const fs::path table = fretbem_test::process_temp_dir() / "kinetic";
  fretbem_test::write_varying_normal_table(table);
  const std::string text =
      "[material]\nE = 210e9\nnu = 0.3\nmu = 0.5\n[grid]\nn = 32\n"
      "length = 2.8e-4\n[surface]\ntype = sphere\nradius = 0.01\n[load]\n"
      "path = table\ncontrol = force\ntable = " +
      table.string() + "\n[friction]\nlaw = static_kinetic\nmu_kinetic = 0.4\n";
  const Scenario sc = parse_scenario(text, "test", fs::temp_directory_path());
  const std::vector<StepRecord> whole = fretbem_test::run_steps(sc);
  auto first = build_model(sc), second = build_model(sc);
  Stepper a(*first), b(*second);
  fretbem_test::StepRecorder head, tail;
  a.run({&head}, 7);
  b.restore(a.state(), a.memory(), a.predictor());
  b.run({&tail});
  ASSERT_EQ(head.rows.size() + tail.rows.size(), whole.size());
  for (std::size_t k = 0; k < tail.rows.size(); ++k) {
    const StepRecord& w = whole[k + 7];
    EXPECT_EQ(tail.rows[k].dissipation, w.dissipation) << "step " << w.step;
    EXPECT_EQ(tail.rows[k].Fx, w.Fx) << "step " << w.step;
    EXPECT_EQ(tail.rows[k].slip_area, w.slip_area) << "step " << w.step;
  }
  fs::remove(table);
}

// The cycle predictor's memory is in the checkpoint: stopped in the third cycle (where every
// increment starts from the remembered traction) and resumed, the run is byte-identical to the
// uninterrupted one (expect_same_run: kx and the work counters aside, as for any resume). A
// checkpoint written without it (an older fretbem) still resumes, with an empty predictor, to the
// same rows within the solver tolerance (1e-10 here: 1e-6 of the force scale, as the predictor test
// below).
TEST(Resume, PredictorMemoryIsCheckpointed) {
  const fs::path d = scenario_file(
      "resume_predictor", sphere_scenario(48, sine_load(0.6, 3, 16), "predictor = cycle\n"));
  const std::string bin = FRETBEM_BINARY, ini = (d / "s.ini").string();
  ASSERT_EQ(sh(bin + " run " + ini + " --quiet --out " + (d / "full").string()), 0);
  ASSERT_EQ(sh(bin + " run " + ini + " --quiet --stop-after 40 --out " + (d / "part").string()), 0);
  ASSERT_EQ(sh("cp -r " + (d / "part").string() + " " + (d / "old").string()), 0);
  ASSERT_EQ(sh(bin + " run --quiet --resume " + (d / "part").string()), 0);
  expect_same_run(d / "full", d / "part");
  // The older checkpoint: no `predictor` dataset.
  ASSERT_EQ(sh("h5ls " + (d / "old" / "checkpoint.h5").string() + " | grep -q predictor"), 0);
  {
    const hid_t f = H5Fopen((d / "old" / "checkpoint.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    ASSERT_GE(H5Ldelete(f, "predictor", H5P_DEFAULT), 0);
    ASSERT_GE(H5Fclose(f), 0);
    reseal_checkpoint(d / "old" / "checkpoint.h5");  // edited on purpose
  }
  ASSERT_EQ(sh(bin + " run --quiet --resume " + (d / "old").string()), 0);
  const auto ra = read_csv(d / "full" / "timeseries.csv"),
             rb = read_csv(d / "old" / "timeseries.csv");
  ASSERT_EQ(ra.size(), rb.size());
  const auto& cols = ra[0];
  const double Fs =
      std::abs(std::stod(ra[4][std::find(cols.begin(), cols.end(), "Fx") - cols.begin()]));
  for (const std::string col : {"Fx", "Ux", "dissipation"}) {
    const std::size_t c = std::size_t(std::find(cols.begin(), cols.end(), col) - cols.begin());
    ASSERT_LT(c, cols.size()) << col;
    const double scale = col == "Fx" ? Fs : std::abs(std::stod(ra.back()[c])) + Fs * 0;
    for (std::size_t i = 1; i < ra.size(); ++i)
      EXPECT_NEAR(std::stod(ra[i][c]), std::stod(rb[i][c]),
                  1e-6 * (col == "Ux" ? std::abs(std::stod(ra[4][c])) : scale))
          << col << " row " << i;
  }
  // A damaged predictor dataset is refused with one line (exit 2), not used.
  ASSERT_EQ(sh(bin + " run " + ini + " --quiet --stop-after 40 --out " + (d / "bad").string()), 0);
  {
    const hid_t f = H5Fopen((d / "bad" / "checkpoint.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    ASSERT_GE(H5Ldelete(f, "predictor", H5P_DEFAULT), 0);
    const hsize_t n = 4;
    const double v[4] = {1, 1, 5, 0};  // five entries announced, none there
    const hid_t sp = H5Screate_simple(1, &n, nullptr);
    const hid_t ds =
        H5Dcreate2(f, "predictor", H5T_IEEE_F64LE, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v), 0);
    H5Dclose(ds), H5Sclose(sp);
    ASSERT_GE(H5Fclose(f), 0);
    reseal_checkpoint(d / "bad" / "checkpoint.h5");
  }
  EXPECT_EQ(
      WEXITSTATUS(std::system(
          (bin + " run --quiet --resume " + (d / "bad").string() + " > /dev/null 2>&1").c_str())),
      2);
  fs::remove_all(d);
}

// solver.predictor = auto (the default) turns the predictor on where a path repeats a load
// transition and off where none repeats; the explicit choices are kept.
TEST(Predictor, AutoPicksCycleOnlyOnRepeatingPaths) {
  auto pick = [](const std::string& load, const std::string& extra = "") {
    return prepare_model(parse_scenario(sphere_scenario(32, load, extra), "t", "."))
        ->cycle_predictor;
  };
  EXPECT_TRUE(pick(sine_load(0.6, 2, 16)));
  EXPECT_FALSE(pick(sine_load(0.6, 2, 16), "predictor = none\n"));
  EXPECT_FALSE(pick(sine_load(0.6, 1, 16)));  // one cycle: nothing comes back (the ramp in)
  EXPECT_FALSE(
      pick("normal_force = 0.015\npath = ramp\nsteps = 6\ncontrol = force\namplitude = 0.9"));
  // Only transitions that come back are remembered: none in the last cycle of a sine.
  LoadPath p = make_load_path(parse_scenario(sphere_scenario(32, sine_load(0.6, 3, 8)), "t", "."));
  const auto later = CyclePredictor::repeated_later(p.steps);
  EXPECT_TRUE(later[1]);  // 0 -> first target: the load of the first step of cycle 2 too
  EXPECT_FALSE(later.back());
  EXPECT_TRUE(later[p.steps.size() - 9]);  // the last step of cycle 2 repeats in cycle 3
}

// A run killed with SIGKILL mid-way keeps readable output and resumes to the same result.
TEST(Resume, KilledRunResumes) {
  const fs::path d = scenario_file(
      "kill", sphere_scenario(96, sine_load(0.6, 3, 64), "[output]\ncheckpoint_every = 1\n"));
  const std::string bin = FRETBEM_BINARY, ini = (d / "s.ini").string();
  ASSERT_EQ(sh(bin + " run " + ini + " --quiet --out " + (d / "full").string()), 0);
  const fs::path part = d / "part";
  const pid_t pid = fork();
  if (pid == 0) {
    execl(bin.c_str(), bin.c_str(), "run", ini.c_str(), "--quiet", "--out", part.c_str(),
          static_cast<char*>(nullptr));
    _exit(127);
  }
  // Kill once a few steps are done (a checkpoint exists), well before the end.
  int status = 0;
  ASSERT_TRUE(fretbem_test::wait_until(
      pid, [&] { return read_csv(part / "timeseries.csv").size() >= 20; }, &status));
  kill(pid, SIGKILL);
  waitpid(pid, &status, 0);
  const auto rows = read_csv(part / "timeseries.csv");
  ASSERT_GE(rows.size(), 2u);
  for (std::size_t i = 1; i < rows.size(); ++i) EXPECT_EQ(rows[i].size(), rows[0].size());
  ASSERT_EQ(sh(bin + " run --quiet --resume " + part.string()), 0);
  expect_same_run(d / "full", part);
  fs::remove_all(d);
}

// solver.predictor = cycle only moves where each increment starts: the rows of a periodic
// history agree with the run without it to the solver tolerance's level (1e-10 here; the
// 1e-6 bound is the one the steady-state test above uses between cycles), and from the third
// cycle on the increments start at the previous cycle's solution, so they cost a fraction of
// the convolutions. Force and displacement control (the QP energy of the start choice has the
// shift term only under displacement control).
TEST(Predictor, CycleStartKeepsTheRowsAndSavesConvolutions) {
  for (const std::string control : {"force", "displacement"}) {
    SCOPED_TRACE(control);
    std::string load = sine_load(0.6, 3, 32);
    if (control == "displacement") {
      load.replace(load.find("control = force"), 15, "control = displacement");
      load += "\ndisplacement_amplitude = " + std::to_string(0.5 * mindlin().ustar);
    }
    const Recorder a = run(sphere_scenario(64, load, "predictor = none\n"));
    const Recorder b = run(sphere_scenario(64, load, "predictor = cycle\n"));
    const Recorder c = run(sphere_scenario(64, load));  // the default (auto) picks cycle
    ASSERT_EQ(b.rows.size(), c.rows.size());
    for (std::size_t k = 0; k < b.rows.size(); ++k) EXPECT_EQ(b.rows[k].Fx, c.rows[k].Fx) << k;
    ASSERT_EQ(a.rows.size(), b.rows.size());
    const double Fs = std::abs(a.rows[8].Fx), Us = std::abs(a.rows[8].Ux);
    long conv_a = 0, conv_b = 0;
    for (std::size_t k = 0; k < a.rows.size(); ++k) {
      EXPECT_NEAR(a.rows[k].Fx, b.rows[k].Fx, 1e-6 * Fs) << k;
      EXPECT_NEAR(a.rows[k].Ux, b.rows[k].Ux, 1e-6 * Us) << k;
      EXPECT_NEAR(a.rows[k].dissipation, b.rows[k].dissipation, 1e-6 * a.rows.back().dissipation)
          << k;
      if (std::isfinite(a.rows[k].kx)) {
        EXPECT_NEAR(a.rows[k].kx, b.rows[k].kx, 1e-6 * a.rows[k].kx);
      }
      if (k > 64) conv_a += a.rows[k].convolutions, conv_b += b.rows[k].convolutions;
    }
    EXPECT_LT(conv_b, conv_a / 3) << conv_a;
  }
}

namespace {

// The traction of every step (one component).
struct TractionRecorder : Observer {
  std::vector<Field> tau;
  std::vector<StepRecord> rows;
  void on_step(const StepRecord& r, const InterfaceState& s, const Model&) override {
    tau.push_back(s.traction[0]), rows.push_back(r);
  }
};

TractionRecorder run_tractions(const std::string& text) {
  auto model = build_model(parse_scenario(text, "test", fs::temp_directory_path()));
  Stepper stepper(*model);
  TractionRecorder r;
  stepper.run({&r});
  return r;
}

}  // namespace

// Masing's rule (Mindlin & Deresiewicz 1953; Jäger 1998) on the incremental solver's own
// states, solved without any warm start (predictor = none): after the reversal at +A the
// traction at load Q is tau_A - 2 tau_v((A - Q) / 2). Sine of 16 steps: the virgin quarter
// records the levels A sin(2 pi j / 16), j = 1..4; at step 12 (Q = -A) the half change A is
// a recorded level, so the image is the virgin traction itself, and inverting the image on the
// unloading branch (record_branch) gives the level A / 2 that step 20 (Q = 0 on the reloading
// branch from -A) needs. Both agree with the solved traction to the solver's accuracy (1e-10
// relative residual; 1e-7 of the largest traction allows for the sqrt(N) one-node error).
TEST(MasingImage, ImageOfTheVirginLoadingIsTheSolvedBranch) {
  const TractionRecorder r =
      run_tractions(sphere_scenario(48, sine_load(0.6, 2, 16), "predictor = none\n"));
  ASSERT_EQ(r.tau.size(), 33u);
  const LoadPath path = make_load_path(parse_scenario(sphere_scenario(48, sine_load(0.6, 2, 16)),
                                                      "test", fs::temp_directory_path()));
  const MasingImage::Plan plan = MasingImage::plan(path, false);
  ASSERT_FALSE(plan.image.empty());
  for (int k = 1; k <= 4; ++k) EXPECT_TRUE(plan.virgin[std::size_t(k)]) << k;
  EXPECT_FALSE(plan.virgin[5]);
  EXPECT_TRUE(plan.turning[4] && plan.turning[12] && plan.turning[20]);
  const Field bound = 0.5 * Field::Ones(48, 48);  // every node kept: tau is zero off contact
  MasingImage m;
  for (std::size_t k = 1; k <= 4; ++k) m.record_virgin(plan.level[k], r.tau[k], bound);
  m.record_turning(plan.level[4], r.tau[4]);
  const double scale = r.tau[4].abs().maxCoeff();
  const VecField* at12 = m.image(plan.level[12]);
  ASSERT_NE(at12, nullptr);
  EXPECT_LT(((*at12)[0] - r.tau[12]).abs().maxCoeff(), 1e-7 * scale);
  for (std::size_t k = 5; k <= 12; ++k) m.record_branch(plan.level[k], r.tau[k], bound);
  m.record_turning(plan.level[12], r.tau[12]);
  const VecField* at20 = m.image(plan.level[20]);
  ASSERT_NE(at20, nullptr);
  EXPECT_LT(((*at20)[0] - r.tau[20]).abs().maxCoeff(), 1e-7 * scale);
}

// With the image the second cycle of a Mindlin–Deresiewicz loop starts every increment at its
// solution (the image on the reloading quarter, the predictor after it), so it costs what a
// steady third cycle costs, and the first cycle's reloading branch pays less than its
// unloading branch; the rows stay those of the run without any warm start
// (Predictor.CycleStartKeepsTheRowsAndSavesConvolutions).
TEST(MasingImage, SecondCycleCostsWhatTheThirdCosts) {
  const Recorder r = run(sphere_scenario(64, sine_load(0.6, 3, 32)));
  long cycle[4] = {0, 0, 0, 0}, unload = 0, reload = 0;
  for (const StepRecord& row : r.rows) cycle[std::min(row.cycle, 3)] += row.convolutions;
  for (int k = 9; k <= 24; ++k) unload += r.rows[std::size_t(k)].convolutions;
  for (int k = 25; k <= 40; ++k) reload += r.rows[std::size_t(k)].convolutions;
  EXPECT_LT(double(cycle[1]), 1.25 * double(cycle[2])) << cycle[1] << " " << cycle[2];
  EXPECT_LT(double(reload), 0.5 * double(unload)) << reload << " " << unload;
}

namespace {

// Cattaneo's virgin traction under displacement control on an n x n grid of the unit square:
// tau_v = mu p0 [sqrt(1 - r^2/a^2) - sqrt((c^2 - r^2)/a^2)], zero where a root's argument is
// negative, with c^2 = a^2 (1 - U/U*) (Johnson eqs. 7.41–7.42 eliminating the force). The
// corrective term squared is linear in U at every node, so the secant through it is exact.
Field cattaneo_traction(int n, double shift_ratio, double mu_p0) {
  const double a = 0.25, c2 = a * a * (1.0 - shift_ratio), h = 1.0 / n;
  Field t = Field::Zero(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double x = (i + 0.5) * h - 0.5, y = (j + 0.5) * h - 0.5, r2 = x * x + y * y;
      if (r2 >= a * a) continue;
      t(i, j) = mu_p0 * (std::sqrt(1.0 - r2 / (a * a)) - std::sqrt(std::max(c2 - r2, 0.0)) / a);
    }
  return t;
}

}  // namespace

// The virgin secant start against Cattaneo's closed form: from the levels U = 0.2 and 0.35 U*
// it gives the traction at 0.5 U* to round-off (the stick zone shrinks by a ring of nodes that
// the secant turns to slip), where the previous level misses it by the whole increment.
TEST(MasingImage, VirginSecantReproducesCattaneo) {
  const int n = 64;
  const double mu_p0 = 1.0;
  const Field bound = cattaneo_traction(n, 1.0, mu_p0);  // mu p: the whole contact slips
  MasingImage m;
  EXPECT_EQ(m.virgin_start(0.2, bound), nullptr);
  m.record_virgin(0.2, cattaneo_traction(n, 0.2, mu_p0), bound);
  m.record_virgin(0.35, cattaneo_traction(n, 0.35, mu_p0), bound);
  const VecField* start = m.virgin_start(0.5, bound);
  ASSERT_NE(start, nullptr);
  const Field exact = cattaneo_traction(n, 0.5, mu_p0);
  const double step = (exact - cattaneo_traction(n, 0.35, mu_p0)).abs().maxCoeff();
  EXPECT_GT(step, 0.05 * mu_p0);
  EXPECT_LT(((*start)[0] - exact).abs().maxCoeff(), 1e-12 * mu_p0);
}

// Masing's rule with the branch secant against the closed form: after the reversal at
// U_T = 0.6 U*, the branch's traction at shift U is tau_T - 2 tau_v((U_T - U)/2). With one
// branch step solved (half change 0.1 U*) the secant runs from the turning point (tau_v = 0
// at half change 0) to 0.2 U*; with two (0.1, 0.2) to 0.25 U*, between the virgin levels
// 0.15 and 0.3 that the interpolated image would use. Both are exact to round-off.
TEST(MasingImage, BranchSecantFollowsMasingsRule) {
  const int n = 64;
  const double ut = 0.6;
  const Field bound = cattaneo_traction(n, 1.0, 1.0);
  auto branch = [&](double u) {
    return (cattaneo_traction(n, ut, 1.0) - 2.0 * cattaneo_traction(n, 0.5 * (ut - u), 1.0)).eval();
  };
  MasingImage m;
  for (const double u : {0.15, 0.3, 0.45, 0.6})
    m.record_virgin(u, cattaneo_traction(n, u, 1.0), bound);
  m.record_turning(ut, cattaneo_traction(n, ut, 1.0));
  m.record_branch(ut - 0.2, branch(ut - 0.2), bound);
  const VecField* second = m.branch_start(ut - 0.4, bound);
  ASSERT_NE(second, nullptr);
  EXPECT_LT(((*second)[0] - branch(ut - 0.4)).abs().maxCoeff(), 1e-12);
  m.record_branch(ut - 0.4, branch(ut - 0.4), bound);
  const VecField* third = m.branch_start(ut - 0.5, bound);
  ASSERT_NE(third, nullptr);
  EXPECT_LT(((*third)[0] - branch(ut - 0.5)).abs().maxCoeff(), 1e-12);
}

// A start that continues the branch (the virgin secant, the Masing image, the branch secant)
// is taken as it is, without building the two force-shifted starts (one product each) to
// compare it with. Without preconditioning an increment's products are its CG steps, the start's
// image and one verifying product per verification pass (counted as an iteration), so convolutions
// - iterations is at most 1 + 1 (1 where the start meets the tolerance), plus one for each update
// of the stick image when the force restoration meets a new stick set; with the shifted starts it
// is 3–4. Checked on the Mindlin–Deresiewicz cycle's virgin steps 2–8 and first unloading 9–24 (32
// steps a cycle).
TEST(MasingImage, ContinuedStartBuildsNoShiftedStarts) {
  const Recorder r =
      run(sphere_scenario(64, sine_load(0.6, 1, 32), "stiffness = none\nprecondition = off\n"));
  int steps = 0, lean = 0;
  for (int k = 2; k <= 24; ++k) {
    const StepRecord& row = r.rows[std::size_t(k)];
    ++steps, lean += row.convolutions - row.tangential_iterations <= 2 ? 1 : 0;
  }
  EXPECT_GE(lean, steps * 3 / 4) << lean << " of " << steps;
}

// A monotone force ramp (no branch follows) starts its steps from the second on at the virgin
// secant, without the force-shifted starts: the same product count as on a cycle's virgin
// quarter (MasingImage.ContinuedStartBuildsNoShiftedStarts), where before every step built
// both shifted starts.
TEST(MasingImage, MonotoneRampStartsOnTheSecant) {
  const std::string ramp = "normal_force = " + std::to_string(hertz_force(1.0 / (1 - 0.09))) +
                           "\npath = ramp\ncontrol = force\namplitude = 0.9\nsteps = 12";
  const Recorder r = run(sphere_scenario(64, ramp, "stiffness = none\nprecondition = off\n"));
  ASSERT_EQ(r.rows.size(), 13u);
  int lean = 0;
  for (std::size_t k = 2; k <= 12; ++k)
    lean += r.rows[k].convolutions - r.rows[k].tangential_iterations <= 2 ? 1 : 0;
  EXPECT_GE(lean, 8) << lean << " of 11";
}

// The virgin secant reads the last two virgin levels, which the checkpoint holds: a ramp
// stopped after step 5 and resumed is byte-identical to the uninterrupted run.
TEST(Resume, RampSecantIsCheckpointed) {
  const std::string ramp = "normal_force = " + std::to_string(hertz_force(1.0 / (1 - 0.09))) +
                           "\npath = ramp\ncontrol = displacement\n"
                           "displacement_amplitude = 0.05\nsteps = 10";
  const fs::path d = scenario_file("resume_ramp", sphere_scenario(48, ramp));
  const std::string bin = FRETBEM_BINARY, ini = (d / "s.ini").string();
  ASSERT_EQ(sh(bin + " run " + ini + " --quiet --out " + (d / "full").string()), 0);
  ASSERT_EQ(sh(bin + " run " + ini + " --quiet --stop-after 5 --out " + (d / "part").string()), 0);
  ASSERT_EQ(sh(bin + " run --quiet --resume " + (d / "part").string()), 0);
  expect_same_run(d / "full", d / "part");
  fs::remove_all(d);
}

// Under a varying normal load the bound of a row is that of the same row one period earlier
// only to the normal solves' error: the predictor's nodes that slipped on it lie just inside
// the new disc. Put on the moved bound, the predictor's start pays under the sampled sine of
// the varying-load bench (F_z = P (1 + 0.3 sin 2 pi t), F_x = 0.5 mu P cos 2 pi t, 16 rows a
// period, three periods): the run costs fewer convolutions than without a predictor (taken
// as they were remembered, 1.43x as many: most increments of the second and third periods
// started at nodes taken for stick nodes with a whole step's slip). The rows agree with the
// run without a predictor to the solver tolerance's level, as at constant load.
TEST(Predictor, VaryingNormalLoadCostsNoMoreThanWithoutIt) {
  const fs::path table = fretbem_test::process_temp_dir() / "varying_predictor.csv";
  fretbem_test::write_sine_normal_table(table, 16, fretbem_test::unit_hertz_force(), 0.5, 3);
  const std::string load = "path = table\ntable = " + table.string() + "\n";
  const Recorder none = run(sphere_scenario(64, load, "stiffness = none\npredictor = none\n"));
  const Recorder cycle = run(sphere_scenario(64, load, "stiffness = none\npredictor = cycle\n"));
  ASSERT_EQ(none.rows.size(), cycle.rows.size());
  long conv_none = 0, conv_cycle = 0;
  const double Fs = std::abs(none.rows[1].Fz) * 0.5, E = none.rows.back().dissipation;
  for (std::size_t k = 0; k < none.rows.size(); ++k) {
    conv_none += none.rows[k].convolutions, conv_cycle += cycle.rows[k].convolutions;
    EXPECT_NEAR(none.rows[k].Fx, cycle.rows[k].Fx, 1e-6 * Fs) << k;
    EXPECT_NEAR(none.rows[k].dissipation, cycle.rows[k].dissipation, 1e-6 * E) << k;
  }
  std::printf("convolutions: predictor = cycle %ld, none %ld\n", conv_cycle, conv_none);
  EXPECT_LE(conv_cycle, conv_none);
}

// The shortcut rows' starts, the corrective solve's along the last row's k_x solution psi and
// k_x's from the secant between the row and the one before it and that psi
// (Stepper::shortcut_start, Stepper::stiffness_start), come from the checkpoint: a Cattaneo
// ramp stopped after step 1 (psi of the full stick set), 2 and 5 and resumed gives the
// uninterrupted run's rows to the bit, k_x included.
TEST(Resume, ShortcutKxStartIsCheckpointed) {
  std::ostringstream ramp;
  ramp << std::setprecision(17) << "normal_force = " << hertz_force(1.0 / (1 - 0.09))
       << "\npath = ramp\ncontrol = displacement\ndisplacement_amplitude = "
       << 0.9 * fretbem_test::unit_full_sliding_shift(0.5) << "\nsteps = 10";
  const fs::path d =
      scenario_file("resume_shortcut", sphere_scenario(48, ramp.str(), "monotone = shortcut\n"));
  const std::string bin = FRETBEM_BINARY, ini = (d / "s.ini").string();
  ASSERT_EQ(sh(bin + " run " + ini + " --quiet --out " + (d / "full").string()), 0);
  const auto full = read_csv(d / "full" / "timeseries.csv");
  ASSERT_EQ(full.size(), 12u);
  for (const int stop : {1, 2, 5}) {
    const fs::path part = d / ("part" + std::to_string(stop));
    ASSERT_EQ(sh(bin + " run " + ini + " --quiet --stop-after " + std::to_string(stop) + " --out " +
                 part.string()),
              0);
    ASSERT_EQ(sh(bin + " run --quiet --resume " + part.string()), 0);
    const auto rows = read_csv(part / "timeseries.csv");
    ASSERT_EQ(rows.size(), 12u);
    // The products differ: the resumed run images p and the slip threshold's C g once more.
    for (std::size_t i = 1; i < full.size(); ++i)
      for (std::size_t c = 0; c < full[0].size(); ++c)
        if (full[0][c] != "convolutions") {
          EXPECT_EQ(full[i][c], rows[i][c])
              << "stop " << stop << " row " << i << " column " << full[0][c];
        }
  }
  fs::remove_all(d);
}

// An increment whose predictor already meets the solver's stopping rule costs the one product
// that images it: under force control the starts it would be compared against (the stick
// nodes shifted to the target force, and every contact node shifted: one product each) are
// not built. Third cycle of a Mindlin–Deresiewicz loop without kx: every step starts at the
// second cycle's solution of the same increment.
TEST(Predictor, ConvergedGuessCostsOneProduct) {
  const Recorder r = run(sphere_scenario(64, sine_load(0.6, 3, 32), "stiffness = none\n"));
  ASSERT_EQ(r.rows.size(), 97u);
  for (std::size_t k = 65; k < r.rows.size(); ++k) {
    EXPECT_EQ(r.rows[k].tangential_iterations, 0) << k;
    EXPECT_EQ(r.rows[k].convolutions, 1) << k;
  }
}

// At one normal load the stepper books a step's slip, states and work on the contact nodes
// only. Checked on every node against the step's own kinematics, s = dU - (u - u0) with dU the
// shift increment: a slip node gains |s| of slip path and g |s| of work (Coulomb, the bound
// fixed within the step), every other contact node nothing; nodes off contact stay open with
// no slip, path or work; the nodal work sums to the dissipation column. Differences of shifts
// carry the round-off of the shift (~1e-16 U), hence the bound 1e-12 of the largest |U|.
struct BookingCheck : Observer {
  std::optional<InterfaceState> last;
  double worst_path = 0.0, worst_work = 0.0, worst_sum = 0.0, max_U = 0.0, total = 0.0;
  long off_contact = 0, slip_steps = 0;
  void on_step(const StepRecord& r, const InterfaceState& s, const Model& m) override {
    const Field g = m.scenario.material.mu * s.pressure;
    max_U = std::max(max_U, std::abs(r.Ux));
    const double h2 = m.scenario.grid.cell_area();
    total = s.dissipation.sum() * h2;
    worst_sum = std::max(worst_sum, std::abs(total - r.dissipation));
    if (last) book(s, g);
    last = s;
  }
  void book(const InterfaceState& s, const Field& g) {
    const double dU = s.shift.x() - last->shift.x();
    for (Eigen::Index k = 0; k < g.size(); ++k) {
      if (!(g(k) > 0.0)) {
        off_contact += s.state(k) != std::uint8_t(NodeState::open) || s.slip[0](k) != 0.0 ||
                       s.slip_path(k) != 0.0 || s.dissipation(k) != 0.0;
        continue;
      }
      const bool slipping = s.state(k) == std::uint8_t(NodeState::slip);
      slip_steps += slipping;
      const double len =
          slipping ? std::abs(dU - (s.displacement[0](k) - last->displacement[0](k))) : 0.0;
      worst_path = std::max(worst_path, std::abs(s.slip_path(k) - last->slip_path(k) - len));
      worst_work =
          std::max(worst_work, std::abs(s.dissipation(k) - last->dissipation(k) - g(k) * len));
    }
  }
};

TEST(Stepper, FixedContactBooksTheContactNodes) {
  const BookingCheck c =
      fretbem_test::run_recorded<BookingCheck>(sphere_scenario(32, sine_load(0.6, 2, 16)));
  EXPECT_GT(c.slip_steps, 0);
  EXPECT_EQ(c.off_contact, 0);
  const double gmax = 0.5 * 1.5 * hertz_force(1.0 / (1 - 0.09)) / (M_PI * 0.25 * 0.25);
  EXPECT_LE(c.worst_path, 1e-12 * c.max_U);
  EXPECT_LE(c.worst_work, 1e-12 * c.max_U * gmax);
  EXPECT_LE(c.worst_sum, 1e-12 * c.total);
}

// At one normal load the record's areas, stick force, contact nodes and slip ring are counted
// on the contact nodes only, with the contact's perimeter counted once. Checked on every step
// against counts over the whole grid made here from the step's states: node by node, the
// perimeter as the faces of contact cells that border an open cell or the domain's edge.
struct AreaCheck : Observer {
  long steps = 0, slip_steps = 0, mismatches = 0;
  void on_step(const StepRecord& r, const InterfaceState& s, const Model& m) override {
    const double a = m.scenario.grid.cell_area();
    const auto st = [&](Eigen::Index i, Eigen::Index j) { return NodeState(s.state(i, j)); };
    const Eigen::Index nx = s.state.rows(), ny = s.state.cols();
    long stick = 0, at_bound = 0, slip = 0, contact = 0, edges = 0;
    double fstick = 0.0;
    for (Eigen::Index j = 0; j < ny; ++j)
      for (Eigen::Index i = 0; i < nx; ++i) {
        const NodeState x = st(i, j);
        if (x == NodeState::open) continue;
        ++contact;
        slip += x == NodeState::slip;
        if (x == NodeState::stick || x == NodeState::stuck_at_bound) {
          ++stick, at_bound += x == NodeState::stuck_at_bound;
          fstick += s.traction[0](i, j);
        }
        const auto open = [&](Eigen::Index p, Eigen::Index q) {
          return p < 0 || q < 0 || p >= nx || q >= ny || st(p, q) == NodeState::open;
        };
        edges += open(i - 1, j) + open(i + 1, j) + open(i, j - 1) + open(i, j + 1);
      }
    ++steps, slip_steps += slip > 0;
    mismatches += r.contact_nodes != contact || r.stick_area != double(stick) * a ||
                  r.stuck_at_bound_area != double(at_bound) * a ||
                  r.slip_area != double(slip) * a ||
                  r.contact_area != double(stick) * a + double(slip) * a ||
                  r.slip_ring_cells != slip_ring_width(slip, edges) ||
                  r.Fx_stick != fstick * m.tangential_operator->direction().x() * a;
  }
};

TEST(Stepper, FixedContactAreasAsOnTheWholeGrid) {
  const AreaCheck c =
      fretbem_test::run_recorded<AreaCheck>(sphere_scenario(32, sine_load(0.6, 2, 16)));
  EXPECT_EQ(c.steps, 33);
  EXPECT_GT(c.slip_steps, 0);
  EXPECT_EQ(c.mismatches, 0);
}

// The image's table is in the checkpoint: stopped on the first unloading branch (step 7 of a
// 16-step sine, where the image starts the increments) and resumed, the run is byte-identical
// to the uninterrupted one.
TEST(Resume, MasingImageIsCheckpointed) {
  const fs::path d = scenario_file("resume_masing", sphere_scenario(48, sine_load(0.6, 2, 16)));
  const std::string bin = FRETBEM_BINARY, ini = (d / "s.ini").string();
  ASSERT_EQ(sh(bin + " run " + ini + " --quiet --out " + (d / "full").string()), 0);
  ASSERT_EQ(sh(bin + " run " + ini + " --quiet --stop-after 7 --out " + (d / "part").string()), 0);
  ASSERT_EQ(sh("h5ls -r " + (d / "part" / "checkpoint.h5").string() + " | grep -q masing"), 0);
  ASSERT_EQ(sh(bin + " run --quiet --resume " + (d / "part").string()), 0);
  expect_same_run(d / "full", d / "part");
  fs::remove_all(d);
}
