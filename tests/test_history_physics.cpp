// History physics: second-order dissipation under a varying normal load, stick areas
// that depend on the state and not on the history, the work of nodes losing contact.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "fretbem/contact/contact_entry.hpp"
#include "fretbem/contact/step_work.hpp"
#include "support/hertz.hpp"
#include "support/temp_dir.hpp"
#include "support/varying_normal_table.hpp"

using namespace fretbem;
namespace fs = std::filesystem;

namespace {

// Hertz sphere, unit domain, R = 1, E = 1, nu = 0.3, mu = 0.5.
std::string sphere_scenario(int n, const std::string& load) {
  return fretbem_test::unit_sphere_ini(n, load, "[solver]\ntolerance = 1e-10\n");
}

fs::path temp_path(const std::string& name) {
  return fretbem_test::process_temp_dir() / name;
}

// Table of F_z = P (1 + 0.3 sin 2 pi t), F_x = 0.5 mu P cos 2 pi t over three periods; with a
// prelude, first a push to F_x = 0.9 mu P and the periodic load one period later.
fs::path varying_normal_table(int rows_per_period, double P, double mu, bool prelude = false) {
  const fs::path f =
      temp_path("varying_" + std::to_string(rows_per_period) + (prelude ? "p" : "")) += ".csv";
  fretbem_test::write_sine_normal_table(f, rows_per_period, P, mu, 3, prelude);
  return f;
}

}  // namespace

// Over a closed cycle of the uncoupled model the normal problem stores no energy (its state
// depends on F_z alone) and the tangential elastic energy returns to its value, so the energy
// dissipated per steady cycle is the loop area of F_x against U_x. The trapezoid loop area is
// second order in the step; the nodal dissipation must be too: the relative difference falls
// by ~4x per halving of the step (the end-of-step traction alone gave -6.8, -4.1, -2.2, -1.1 %
// at 16 ... 128 rows: first order). n = 48 (a = 12 cells): the comparison is one of time
// discretisation on one grid, so the spatial resolution does not enter; measured orders 2.0-2.1.
// One solve a row (load.substeps = 1): the discretisation whose order this is.
TEST(Dissipation, SecondOrderUnderVaryingNormalLoad) {
  const double P = fretbem_test::unit_hertz_force(), mu = 0.5;
  std::vector<double> diff;
  for (int rows : {16, 32, 64, 128}) {
    const fs::path table = varying_normal_table(rows, P, mu);
    const auto r = fretbem_test::run_steps(
        sphere_scenario(48, "path = table\nsubsteps = 1\ntable = " + table.string()));
    fs::remove(table);
    const fretbem_test::CycleEnergy e = fretbem_test::cycle_energy(r, 2);
    diff.push_back(e.nodal / e.loop - 1);
    std::printf("rows/period %3d: nodal / loop - 1 = %+.3e\n", rows, diff.back());
  }
  for (std::size_t k = 1; k < diff.size(); ++k) {
    const double order = std::log2(std::abs(diff[k - 1] / diff[k]));
    std::printf("observed order %.2f\n", order);
    EXPECT_GT(order, 1.8);
  }
  EXPECT_LT(std::abs(diff[2]), 2e-3);  // 64 rows per period
}

// Two histories that reach the same steady cycle (the periodic load above, once from the
// virgin state and once after a push to 0.9 mu P) have the same slip in it (Barber: with the
// normal-tangential coupling absent the steady slip does not depend on the initial state), but
// different locked-in tractions in the permanent stick zone. Stick areas classified by the
// slip of the step agree; the part on the bound without slipping is what differs.
TEST(StickArea, DependsOnTheStateNotOnTheHistory) {
  const double P = fretbem_test::unit_hertz_force(), mu = 0.5;
  const int rows = 32;
  std::vector<std::vector<StepRecord>> runs;
  for (bool prelude : {false, true}) {
    const fs::path table = varying_normal_table(rows, P, mu, prelude);
    runs.push_back(
        fretbem_test::run_steps(sphere_scenario(48, "path = table\ntable = " + table.string())));
    fs::remove(table);
  }
  const double cell = std::pow(1.0 / 48, 2);
  double worst_stick = 0, worst_slip = 0, worst_traction = 0;
  const std::size_t last = runs[0].size() - 1;
  for (std::size_t k = last - rows + 1; k <= last; ++k) {
    const StepRecord &a = runs[0][k], &b = runs[1][k];
    ASSERT_NEAR(a.time, b.time, 1e-12);
    worst_stick = std::max(worst_stick, std::abs(a.stick_area - b.stick_area) / cell);
    // The traction classification: on the bound counts as slip.
    const double old_a = a.stick_area - a.stuck_at_bound_area;
    worst_traction =
        std::max(worst_traction, std::abs(old_a - b.stick_area + b.stuck_at_bound_area) / cell);
    worst_slip = std::max(worst_slip, std::abs(a.slip_area - b.slip_area) / cell);
  }
  std::printf("steady cycle: max |stick area difference| = %.0f cells, slip %.0f cells\n",
              worst_stick, worst_slip);
  std::printf("classified by traction (on the bound = slip): %.0f cells apart\n", worst_traction);
  EXPECT_EQ(worst_stick, 0.0);
  EXPECT_EQ(worst_slip, 0.0);
}

namespace {

// A steel sphere (R = 10 mm, n = 32) or a rough surface under a table whose normal load falls
// by up to half within a step while the tangential load reverses: nodes at the contact's edge
// open within those steps. Force or displacement control, analogy or Cerruti operator.
std::string opening_scenario(bool rough, bool displacement, bool cerruti, const fs::path& table) {
  std::ostringstream s;
  s << "[material]\nE = 210e9\nnu = 0.3\nmu = 0.5\n[grid]\nn = 32\nlength = 2.8e-4\n[surface]\n"
    << (rough ? "type = rough\nhurst = 0.7\nrms_height = 3e-7\nseed = 3\n"
              : "type = sphere\nradius = 0.01\n")
    << "[load]\npath = table\ntable = " << table.string()
    << "\ncontrol = " << (displacement ? "displacement" : "force")
    << "\n[solver]\nstiffness = false\ntolerance = 1e-9\ncoupling = "
    << (cerruti ? "cerruti" : "analogy") << "\n";
  return s.str();
}

fs::path opening_table(bool displacement) {
  const fs::path f = temp_path(displacement ? "opening_ux" : "opening_fx") += ".csv";
  std::ofstream(f) << (displacement ? "time,Fz,Ux\n0,10,0\n1,12,2e-7\n2,7,-1e-7\n3,11,1.5e-7\n"
                                      "4,6,-1e-7\n5,10,0\n6,12,2e-7\n7,7,-1e-7\n"
                                    : "time,Fz,Fx\n0,10,0\n1,12,2.5\n2,7,-1.5\n3,11,2\n"
                                      "4,6,-1.2\n5,10,0\n6,12,2.5\n7,7,-1.5\n");
  return f;
}

}  // namespace

// Frictional work is tau . s with tau on its bound and parallel to s, so no node's dissipation
// and no row's may fall. A node that opens within a step slips while its falling bound
// carries it; the start traction dotted with its whole step displacement (which goes on after
// it opened), halved, made a node's dissipation fall by up to 7 % of the run's total and a
// row's by up to 0.9 of it in these cases.
TEST(Dissipation, NeverDecreasesWhenNodesOpen) {
  for (bool rough : {false, true})
    for (bool displacement : {false, true})
      for (bool cerruti : {false, true}) {
        const fs::path table = opening_table(displacement);
        auto m = build_model(parse_scenario(opening_scenario(rough, displacement, cerruti, table),
                                            "opening", fs::temp_directory_path()));
        Stepper st(*m);
        double worst_row = 0.0, worst_node = 0.0;
        int opened = 0;
        for (std::size_t k = 0; k < st.steps(); ++k) {
          const Field node0 = st.state().dissipation;
          const Field p0 = st.state().pressure;
          const double row0 = st.memory().dissipation;
          st.advance(k);
          opened += int(((p0 > 0.0) && (st.state().pressure == 0.0)).count());
          worst_row = std::min(worst_row, st.memory().dissipation - row0);
          worst_node = std::min(worst_node, (st.state().dissipation - node0).minCoeff());
        }
        fs::remove(table);
        const double total = st.memory().dissipation, h2 = m->scenario.grid.cell_area();
        std::printf("%s %s %s: %d openings; worst increment / total: row %.2g, node %.2g\n",
                    rough ? "rough" : "sphere", displacement ? "displacement" : "force",
                    cerruti ? "cerruti" : "analogy", opened, worst_row / total,
                    worst_node * h2 / total);
        SCOPED_TRACE(std::string(rough ? "rough" : "sphere") +
                     (displacement ? ", displacement" : ", force") +
                     (cerruti ? ", cerruti" : ", analogy"));
        ASSERT_GT(opened, 0);
        ASSERT_GT(st.memory().dissipation, 0.0);
        EXPECT_GE(worst_row, 0.0);
        EXPECT_GE(worst_node, 0.0);
      }
}

namespace {

// F_z rising from P / 100 to P in `rows` rows with F_x = lambda F_z from the first row on.
fs::path proportional_table(int rows, double P, double lambda) {
  const fs::path f = temp_path("proportional_" + std::to_string(rows)) += ".csv";
  std::ofstream out(f);
  out << std::setprecision(17) << "time,Fz,Fx\n";
  for (int k = 0; k <= rows; ++k) {
    const double Fz = P * (0.01 + 0.99 * double(k) / rows);
    out << double(k) / rows << "," << Fz << "," << (k > 0 ? lambda * Fz : 0.0) << "\n";
  }
  return f;
}

struct FinalState : fretbem_test::StepRecorder {
  InterfaceState state;
  void on_finish(const InterfaceState& s, const Model&) override { state = s; }
};

// rms of tau_x - lambda p over the contact nodes outside half the final contact radius (those
// the ramp took in after F_z passed P / 8), relative to lambda p_max, at the ramp's end.
double proportional_traction_error(int rows, const std::string& coupling, double nu) {
  const double mu = 0.5, lambda = 0.25, P = fretbem_test::unit_hertz_force();
  const int n = 48;
  const fs::path table = proportional_table(rows, P, lambda);
  std::ostringstream ini;
  ini << "[material]\nE = 1\nnu = " << nu << "\nmu = " << mu << "\n[grid]\nn = " << n
      << "\nlength = 1\n[surface]\ntype = sphere\nradius = 1\n[load]\n"
      << "path = table\nsubsteps = 1\ntable = " << table.string()
      << "\n[solver]\ntolerance = 1e-10\n"
      << "stiffness = none\ncoupling = " << coupling << "\n";
  const auto r = fretbem_test::run_recorded<FinalState>(ini.str());
  fs::remove(table);
  const Field& p = r.state.pressure;
  const Field& tau = r.state.traction[0];
  double sum = 0.0;
  int count = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = (i + 0.5) / n - 0.5, y = (j + 0.5) / n - 0.5;
      if (!(p(i, j) > 0.0) || std::hypot(x, y) < 0.125) continue;  // a = 1/4 at P
      sum += std::pow(tau(i, j) - lambda * p(i, j), 2), ++count;
    }
  return std::sqrt(sum / count) / (lambda * p.maxCoeff());
}

}  // namespace

// Oblique loading, F_x = lambda F_z rising together with lambda < mu: nothing slips
// (Mindlin & Deresiewicz 1953; Johnson, Contact Mechanics, ch. 7, simultaneous variation of
// normal and tangential forces). Where the tangential kernel has the shape of the normal one
// (the analogy; Cerruti at nu = 0) the traction is tau = lambda p on the grid as in the
// continuum. The ring of nodes each step brings into contact touches part-way through it;
// glued over the whole step, it stores a traction error of the order of the step: measured
// rms 3.2e-2, 1.8e-2, 8.7e-3 at 16, 32, 64 rows on the analogy (order 0.94 from 16 to 64),
// 3.7e-2, 1.8e-2, 9.3e-3 on Cerruti (0.99). Stuck from where it touched: 1.1e-2, 2.6e-3,
// 7.7e-4 (order 1.93) and 7.5e-3, 2.4e-3, 1.1e-3 (1.36). What remains is first order but
// smaller: the initial contact, glued with no traction at P / 100, and the linearised
// touching time (1.9e-4 at 256 rows, 9.7e-5 at 512 on the analogy). The bounds separate the
// two: an order above 1.2 and, at 64 rows, a quarter of the glued error. One solve a row
// (load.substeps = 1): the step is the row.
TEST(Traction, ProportionalLoadingSecondOrderInTheStep) {
  for (const auto& [coupling, nu] : {std::pair<std::string, double>{"analogy", 0.3},
                                     std::pair<std::string, double>{"cerruti", 0.0}}) {
    const double e16 = proportional_traction_error(16, coupling, nu);
    const double e64 = proportional_traction_error(64, coupling, nu);
    const double order = 0.5 * std::log2(e16 / e64);
    std::printf(
        "%s: rms (tau - lambda p) / (lambda p_max) %.3e at 16 rows, %.3e at 64: order "
        "%.2f\n",
        coupling.c_str(), e16, e64, order);
    EXPECT_GT(order, 1.2) << coupling;
    EXPECT_LT(e64, 2.2e-3) << coupling;
  }
}

// A node losing contact in a step opens where its contact function, p0 > 0 in contact and
// -gap / c_nn open, crosses zero on the line between the step's ends.
TEST(ContactLoss, OpensWhereTheContactFunctionCrossesZero) {
  Field gap1(1, 4), p0(1, 4), p1(1, 4), theta;
  gap1 << 3e-9, 0.0, 0.0, 1e-9;
  p0 << 2.0, 2.0, 0.0, 1.0;
  p1 << 0.0, 0.0, 0.0, 0.5;
  const double c_nn = 1e-9;  // m/Pa
  loss_fraction(gap1, p0, p1, c_nn, theta);
  EXPECT_DOUBLE_EQ(theta(0), 2e-9 / (2e-9 + 3e-9));  // -gap1 / c_nn = -3, p0 = 2
  EXPECT_DOUBLE_EQ(theta(1), 1.0);                   // at zero gap: opened at the step's end
  EXPECT_DOUBLE_EQ(theta(2), 1.0);                   // open throughout
  EXPECT_DOUBLE_EQ(theta(3), 1.0);                   // in contact throughout
}

// The work of a node that slips with its bound falling linearly from g0 to zero at theta and
// is free after it: its free motion f (the slip it would make carrying no traction) is linear
// in the step, and while on the bound its own traction's release c_tt g0 adds to it, so
// integrating g along that slip in 2000 sub-intervals gives the closed form of step_work.hpp.
TEST(ContactLoss, WorkIsTheBoundAlongTheSlipBeforeTheNodeOpened) {
  const double g0 = 3.0, c_tt = 2e-3, theta = 0.4, f = 5e-3;  // Pa, m/Pa, -, m over the step
  double work = 0.0;
  const int m = 2000;
  for (int i = 0; i < m; ++i) {  // midpoint rule on [0, theta]: exact for the linear g
    const double t = (i + 0.5) / m * theta, g = g0 * (1 - t / theta);
    work += g * (f + c_tt * g0 / theta) * theta / m;
  }
  InterfaceState end;
  end.pressure = Field::Zero(1, 1);
  end.state = StateField::Constant(1, 1, std::uint8_t(NodeState::open));
  const Field g1 = Field::Zero(1, 1), start_bound = Field::Constant(1, 1, g0);
  const Field start_p = Field::Constant(1, 1, 2 * g0), loss = Field::Constant(1, 1, theta);
  const StateField before = StateField::Constant(1, 1, std::uint8_t(NodeState::slip));
  const VecField tau0{Field::Constant(1, 1, g0)};
  const VecField s{Field::Constant(1, 1, f + c_tt * g0)};  // the whole step's s = f + c_tt tau0
  StepStart start{start_bound, start_p, before, tau0, &loss, c_tt};
  StepWork out;
  out.slip = s[0].abs();
  step_work(&start, end, g1, s, out);
  EXPECT_NEAR(out.work(0), work, 1e-12 * work);
  EXPECT_NEAR(out.pressure(0) * out.slip(0) * 0.5, out.work(0), 1e-15 * work);  // mu = 1/2
  start.loss = nullptr;  // opened at the step's end: the whole slip on the falling bound
  step_work(&start, end, g1, s, out);
  EXPECT_DOUBLE_EQ(out.work(0), 0.5 * g0 * (f + c_tt * g0));
}

// The three-point rule (step_work.hpp, start.before): a node slipping through two steps of
// unequal spans h0, h1 with its bound quadratic and its slip rate linear in time; the work of
// the second step is exact (against the antiderivative of g times the rate), where the
// trapezoid alone is not. The pressure along the slip takes the same weights, so with the
// bound mu p Archard's k p |s| is (k / mu) x the work to round-off. A node that did not slip
// through the step before (its slip there 0) keeps the trapezoid.
TEST(ThreePointRule, ExactForAQuadraticBoundAndLinearSlipRateAcrossUnequalSteps) {
  const double mu = 0.4;
  const double a = 3.0, b = -1.7, c = 2.3;  // g(t) = a + b t + c t^2 (Pa)
  const double d = 0.8, e = -0.45;          // slip rate d + e t (m per unit time)
  auto g = [&](double t) { return a + t * (b + c * t); };
  auto slip = [&](double t0, double t1) { return d * (t1 - t0) + 0.5 * e * (t1 * t1 - t0 * t0); };
  auto work = [&](double t0, double t1) {
    auto F = [&](double t) {
      return a * d * t + (a * e + b * d) * t * t / 2 + (b * e + c * d) * t * t * t / 3 +
             c * e * t * t * t * t / 4;
    };
    return F(t1) - F(t0);
  };
  const auto slipping = std::uint8_t(NodeState::slip);
  for (const auto& [h0, h1] : {std::pair{0.1, 0.1}, std::pair{0.1, 0.025}, std::pair{0.03, 0.2}}) {
    const double t0 = 0.4, t1 = t0 + h0, t2 = t1 + h1;
    InterfaceState end;
    end.pressure = Field::Constant(1, 1, g(t2) / mu);
    end.state = StateField::Constant(1, 1, slipping);
    const Field g1 = Field::Constant(1, 1, g(t2)), g0 = Field::Constant(1, 1, g(t1));
    const Field p0 = g0 / mu;
    const StateField before = StateField::Constant(1, 1, slipping);
    const VecField tau0{g0};
    const VecField s{Field::Constant(1, 1, slip(t1, t2))};
    const Field dg0 = Field::Constant(1, 1, g(t1) - g(t0)), dp0 = dg0 / mu;
    const Field s0 = Field::Constant(1, 1, slip(t0, t1));
    const StepBefore prior{dg0, dp0, s0, h0, h1};
    StepStart start{g0, p0, before, tau0};
    start.before = &prior;
    StepWork out;
    out.slip = s[0].abs();
    step_work(&start, end, g1, s, out);
    const double exact = work(t1, t2);
    EXPECT_NEAR(out.work(0), exact, 1e-13 * exact) << h0 << " " << h1;
    EXPECT_NEAR(mu * out.pressure(0) * out.slip(0), out.work(0), 1e-15 * exact);
    const double trapezoid = 0.5 * (g(t1) + g(t2)) * slip(t1, t2);
    EXPECT_GT(std::abs(trapezoid - exact), 1e-6 * exact);  // the trapezoid is not exact
    const Field none = Field::Zero(1, 1);
    const StepBefore not_through{dg0, dp0, none, h0, h1};
    start.before = &not_through;
    step_work(&start, end, g1, s, out);
    EXPECT_DOUBLE_EQ(out.work(0), trapezoid);
  }
}

namespace {

// F_x ramped to 0.6 mu P at F_z = P, then F_z lowered to 0.7 P in `rows` rows at that F_x,
// each split into `split` equal rows along the same line; returns the dissipation of the
// lowering (J). Unit sphere, n = 32 (a = 8 cells at P).
double lowering_dissipation(int rows, int split) {
  const double P = fretbem_test::unit_hertz_force(), mu = 0.5, Fx = 0.6 * mu * P;
  const fs::path table =
      temp_path("lowering_" + std::to_string(rows) + "_" + std::to_string(split)) += ".csv";
  {
    std::ofstream out(table);
    out << std::setprecision(17) << "time,Fz,Fx\n0," << P << ",0\n1," << P << "," << Fx << "\n";
    for (int j = 1; j <= rows * split; ++j)
      out << 1.0 + double(j) / (rows * split) << "," << P * (1 - 0.3 * j / (rows * split)) << ","
          << Fx << "\n";
  }
  const auto r = fretbem_test::run_steps(
      fretbem_test::unit_sphere_ini(32, "path = table\ntable = " + table.string(),
                                    "[solver]\ntolerance = 1e-10\nstiffness = none\n"));
  fs::remove(table);
  double at_ramp_end = 0.0;
  for (const StepRecord& rec : r)
    if (std::abs(rec.time - 1.0) < 1e-12) at_ramp_end = rec.dissipation;
  return r.back().dissipation - at_ramp_end;
}

}  // namespace

// Lowering F_z under a held F_x: the contact shrinks, and the edge nodes slip with their
// falling bound until they open. Their work is that slip's, not the free motion after they
// opened: booked over the whole step (tau0 . s / 2), the two-row lowering dissipated 1.36e-2
// more than its step limit (Richardson, order 2, from 16 and 32 sub-rows a row), 2 sub-rows
// 2.6e-3. Up to the fraction of the step at which each node opened: -1.4e-4 and +4.8e-4, and
// +2.8e-4 at 4 sub-rows: what remains is the slip phase's second-order quadrature
// (docs/algorithms.md, "A moving bound within a step"); 1e-3 holds it with a factor 2.
TEST(ContactLoss, LoweringTheNormalLoadConvergesToItsStepLimit) {
  const double d16 = lowering_dissipation(2, 16), d32 = lowering_dissipation(2, 32);
  const double limit = d32 + (d32 - d16) / 3.0;
  for (int split : {1, 2}) {
    const double error = lowering_dissipation(2, split) / limit - 1.0;
    std::printf("lowering F_z in 2 rows of %d sub-rows: dissipation %+.3e off its limit\n", split,
                error);
    EXPECT_LT(std::abs(error), 1e-3) << split << " sub-rows a row";
  }
}
