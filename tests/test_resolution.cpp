// Resolution and domain reports: the slip-ring measure against an annulus, the choice of a
// cycle's peak among equal loads, the edge load share, Hertz predictions of `fretbem check`,
// warnings and refusals of a run.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <tuple>
#include <vector>

#include "fretbem/history/cycle_summary.hpp"
#include "fretbem/history/resolution.hpp"
#include "support/cli.hpp"
#include "support/csv_text.hpp"
#include "support/hertz.hpp"

using namespace fretbem;
namespace fs = std::filesystem;

namespace {

// Annulus c < r < a of slip around a stick disc, centred on an n x n grid (radii in cells).
StateField annulus(int n, double a, double c) {
  StateField s = StateField::Zero(n, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double r = std::hypot(i + 0.5 - n / 2.0, j + 0.5 - n / 2.0);
      if (r < a) s(i, j) = std::uint8_t(r < c ? NodeState::stick : NodeState::slip);
    }
  return s;
}

using Result = fretbem_test::CliResult;

fs::path work_dir() {
  return fretbem_test::process_dir("fretbem_resolution");
}

Result cli(const std::string& args) {
  return fretbem_test::run_fretbem(args, "fretbem_resolution");
}

// Hertz sphere, E = 1, nu = 0.3, R = 1, mu = 0.5, at the force giving a = 1/4 on a unit domain.
std::string sphere_ini(int n, const std::string& load, double length = 1.0) {
  return fretbem_test::unit_sphere_ini(
      n, "normal_force = " + format_number(fretbem_test::unit_hertz_force()) + "\n" + load,
      "[solver]\nstiffness = false\n", 0.5, length);
}

fs::path write_ini(const std::string& name, const std::string& text) {
  const fs::path f = work_dir() / (name + ".ini");
  std::ofstream(f) << text;
  return f;
}

std::vector<std::string> read_lines(const fs::path& f) {
  std::ifstream in(f);
  std::vector<std::string> out;
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

// The unit sphere's [load] body of a displacement path to `ratio` times the full-sliding shift
// u* = mu delta E*/G* (delta = a^2/R = 1/16, mu = 0.5; Ciavarella–Jäger), then `rest`.
std::string displacement_load(const std::string& path, double ratio, const std::string& rest) {
  const double ustar = fretbem_test::unit_full_sliding_shift(0.5);
  std::ostringstream load;
  load.precision(17);
  load << "path = " << path
       << "\ncontrol = displacement\ndisplacement_amplitude = " << ratio * ustar << "\n"
       << rest;
  return load.str();
}

}  // namespace

// (a^2 - c^2) / (2a) for annuli from thin to thick, a = 40 cells: the digitised ring's measure
// within 0.2 cells (the staircase estimate of the edge length is good to ~1 % on a disc).
TEST(SlipRing, MeasuresTheWidthOfAnAnnulus) {
  for (double c : {38.0, 36.0, 32.0, 20.0}) {
    const double a = 40.0, want = (a * a - c * c) / (2 * a);
    const double got = slip_ring_cells(annulus(128, a, c));
    std::printf("a = 40, c = %.0f: ring %.3f cells, closed form %.3f\n", c, got, want);
    EXPECT_NEAR(got, want, 0.2);
  }
  EXPECT_EQ(slip_ring_cells(annulus(64, 20, 20)), 0.0);  // nothing slips
  EXPECT_EQ(contact_nodes(annulus(64, 20, 10)), (annulus(64, 20, 10) != 0).count());
}

TEST(EdgeLoad, ShareOfTheOutermostCells) {
  EXPECT_NEAR(edge_load_share(Field::Ones(10, 10)), 36.0 / 100.0, 1e-15);
  Field p = Field::Zero(10, 10);
  p(5, 5) = 1.0;
  EXPECT_EQ(edge_load_share(p), 0.0);
  p(0, 3) = 1.0;
  EXPECT_NEAR(edge_load_share(p), 0.5, 1e-15);
}

// The run's ring at the turning points against Mindlin's c/a = (1 - q)^(1/3) for a = 32 cells:
// within one cell (the digitised edge of the contact and of the stick disc each move by up to
// half a cell), and the same prediction `fretbem check` prints.
TEST(SlipRing, RunMatchesTheMindlinRingAndCheckPredictsIt) {
  const std::string load =
      "path = sine\ncontrol = force\namplitude = 0.3\ncycles = 1\n"
      "steps_per_cycle = 16";
  const Scenario sc = parse_scenario(sphere_ini(128, load), "ring", work_dir());
  auto model = build_model(sc);
  Stepper stepper(*model);
  struct : Observer {
    double ring = -1;
    StepRecord prev;
    void on_step(const StepRecord& r, const InterfaceState&, const Model&) override {
      if (load_peak(r, prev) && (ring < 0 || r.slip_ring_cells < ring)) ring = r.slip_ring_cells;
      prev = r;
    }
  } narrowest;
  stepper.run({&narrowest});
  const double want = 32 * (1 - closed_forms::cattaneo_stick_ratio(0.3));
  std::printf("ring at the turning points %.3f cells, Mindlin %.3f\n", narrowest.ring, want);
  EXPECT_NEAR(narrowest.ring, want, 1.0);
  const auto p = predict_sphere(sc);
  ASSERT_TRUE(p.has_value());
  EXPECT_NEAR(p->a_over_h, 32.0, 1e-9);
  EXPECT_NEAR(p->ring_cells, want, 1e-9);
  EXPECT_EQ(p->edge_share, 0.0);
  // The contact's share of the unit domain, pi a^2 with a = 1/4: 19.6 %.
  const auto lines = describe(*p, sc);
  EXPECT_NE(lines.front().find("(19.6 % of the domain)"), std::string::npos) << lines.front();
}

// q = 0.05 at n = 64 (a = 16 cells): the ring a (1 - 0.95^(1/3)) = 0.27 cells. check warns and
// suggests a grid that gives two cells; the run warns on stderr and still exits 0.
TEST(SlipRing, UnderResolvedRingWarnsInCheckAndRun) {
  const std::string load =
      "path = sine\ncontrol = force\namplitude = 0.05\ncycles = 1\n"
      "steps_per_cycle = 8";
  const fs::path ini = write_ini("thin", sphere_ini(64, load));
  const Result c = cli("check " + ini.string());
  EXPECT_EQ(c.status, 0);
  EXPECT_NE(c.out.find("warning: the slip ring spans under 2 cells"), std::string::npos) << c.out;
  const int suggested =
      int(std::ceil(2.0 / (0.25 * (1 - closed_forms::cattaneo_stick_ratio(0.05)))));
  EXPECT_NE(c.out.find("grid.n >= " + std::to_string(suggested)), std::string::npos) << c.out;
  const fs::path out = work_dir() / "thin_run";
  fs::remove_all(out);
  const Result r = cli("run " + ini.string() + " --out " + out.string());
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("WARNING"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("resolution: slip ring"), std::string::npos) << r.out;
  const auto rows = read_lines(out / "cycles.csv");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].rfind("cycle,steps,dissipated_energy,loop_area,Fx_amplitude,Ux_amplitude,"
                          "kx_at_max,kx_at_min,slip_area_at_peak,",
                          0),
            0u);  // the old columns first, unchanged
  EXPECT_NE(rows[0].find(",slip_ring_cells,contact_nodes,a_over_h"), std::string::npos);
  fs::remove_all(out);
}

// A displacement sine at three times the full-sliding shift u* = mu delta E*/G* (delta = a^2/R,
// Ciavarella–Jäger): the whole contact slides at every load peak, which the report says instead
// of a "ring" that is only half the contact radius.
TEST(SlipRing, GrossSlipAtThePeaksIsReportedAsSuch) {
  const fs::path ini = write_ini(
      "gross", sphere_ini(32, displacement_load("sine", 3.0, "cycles = 1\nsteps_per_cycle = 8")));
  const fs::path out = work_dir() / "gross_run";
  fs::remove_all(out);
  const Result r = cli("run " + ini.string() + " --quiet --out " + out.string());
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("resolution: the whole contact slides at the load peaks"), std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("slip ring 4"), std::string::npos) << r.out;  // a/2 = 4 cells
  EXPECT_EQ(r.err.find("WARNING"), std::string::npos) << r.err;
  fs::remove_all(out);
}

// A rough displacement ramp that ends in partial slip with thin slip zones (n = 32): the
// warning speaks of slip zones at the end of the ramp, not of a sphere's ring, Mindlin–
// Deresiewicz or load peaks.
TEST(SlipRing, RoughRampWarnsInRoughSurfaceWords) {
  const fs::path out = work_dir() / "rough_run";
  fs::remove_all(out);
  const Result r = cli("run " + std::string(FRETBEM_SOURCE_DIR) +
                       "/scenarios/rough_monotone.ini --quiet --set grid.n=32 --set "
                       "load.displacement_amplitude=1e-6 --set load.steps=4 --out " +
                       out.string());
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("resolution: slip zones"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("slip zones (per unit length of contact edge) at the end of the ramp"),
            std::string::npos)
      << r.err;
  for (const char* sphere_words : {"Mindlin", "load peaks", "slip ring"})
    EXPECT_EQ(r.err.find(sphere_words), std::string::npos) << r.err;
  fs::remove_all(out);
}

// A sphere whose Hertz contact (a = 1/4) does not fit a domain of side 0.4: a run refuses it
// (exit 2, one line naming the key) and check with it, the same line; with
// grid.allow_edge_contact = true check predicts it and the run goes on with a warning giving
// the share; the same contact on a domain of side 1 is silent.
TEST(EdgeLoad, ContactLargerThanTheGridIsRefusedUnlessAllowed) {
  const fs::path ini = write_ini("edge", sphere_ini(32, "", 0.4));
  const fs::path out = work_dir() / "edge_run";
  fs::remove_all(out);
  const Result r = cli("run " + ini.string() + " --quiet --out " + out.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("grid.allow_edge_contact"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1);
  fs::remove_all(out);
  const Result c = cli("check " + ini.string() + " --out " + out.string());
  EXPECT_EQ(c.status, 2);
  EXPECT_EQ(c.err, r.err);
  const Result allowed =
      cli("check " + ini.string() + " --set grid.allow_edge_contact=true --out " + out.string());
  EXPECT_EQ(allowed.status, 0);
  EXPECT_NE(allowed.out.find("reaches the outermost cells"), std::string::npos) << allowed.out;
  const Result ok = cli("run " + ini.string() +
                        " --quiet --set grid.allow_edge_contact=true --out " + out.string());
  EXPECT_EQ(ok.status, 0) << ok.err;
  EXPECT_NE(ok.err.find("of the normal load is on the outermost cells"), std::string::npos);
  fs::remove_all(out);
  const fs::path fits = write_ini("fits", sphere_ini(32, ""));
  const Result quiet = cli("run " + fits.string() + " --quiet --out " + out.string());
  EXPECT_EQ(quiet.status, 0);
  EXPECT_EQ(quiet.err, "");
  fs::remove_all(out);
}

// A displacement ramp to half the full-sliding shift u* = mu delta E*/G* (delta = a^2/R):
// check and run say U*/amplitude = 2, and cycles.csv has its header and no rows.
TEST(Ramp, DisplacementRampBelowSlidingIsReportedAndWritesNoCycleRows) {
  const fs::path ini =
      write_ini("ramp", sphere_ini(64, displacement_load("ramp", 0.5, "steps = 4")));
  const Result c = cli("check " + ini.string());
  EXPECT_NE(c.out.find("ends below full sliding: U*/amplitude = 2"), std::string::npos) << c.out;
  const fs::path out = work_dir() / "ramp_run";
  fs::remove_all(out);
  const Result r = cli("run " + ini.string() + " --quiet --out " + out.string());
  EXPECT_EQ(r.status, 0) << r.err;
  // The run's U* uses its own delta (n = 64: within 1 % of Hertz's): "U*/amplitude = 1.9x/2".
  const auto at = r.err.find("U*/amplitude = ");
  ASSERT_NE(at, std::string::npos) << r.err;
  EXPECT_NEAR(std::stod(r.err.substr(at + 15)), 2.0, 0.04);
  EXPECT_EQ(read_lines(out / "cycles.csv").size(), 1u);
  fs::remove_all(work_dir());
}

// A contact that grows past the domain during the history (a table raising F_z 27-fold:
// a = 1/4 -> 3/4 on a domain of side 1): the run refuses it at the step where it happens
// (exit 2, one line naming the step and the key), and check with the same line, found from
// the table's largest F_z; on a periodic grid the same history runs without a warning.
TEST(EdgeLoad, ContactGrowingPastTheGridDuringTheHistory) {
  const double F0 = fretbem_test::unit_hertz_force();
  std::ofstream(work_dir() / "grow.csv") << std::setprecision(17) << "time,Fz,Fx\n0," << F0
                                         << ",0\n1," << 2 * F0 << ",0\n2," << 27 * F0 << ",0\n";
  const std::string text =
      "[material]\nE = 1\nnu = 0.3\nmu = 0.5\n[grid]\nn = 32\nlength = 1\n"
      "[surface]\ntype = sphere\nradius = 1\n[load]\npath = table\ntable = grow.csv\n"
      "[solver]\nstiffness = false\n";
  const fs::path ini = write_ini("grow", text);
  const fs::path out = work_dir() / "grow_run";
  fs::remove_all(out);
  const Result r = cli("run " + ini.string() + " --quiet --out " + out.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err.rfind("fretbem: error: step 2: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("grid.allow_edge_contact"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1);
  fs::remove_all(out);
  const Result c = cli("check " + ini.string() + " --no-estimate --out " + out.string());
  EXPECT_EQ(c.status, 2);
  EXPECT_EQ(c.err, r.err);
  std::string ptext = text;
  ptext.replace(ptext.find("length = 1\n"), 11, "length = 1\nperiodic = true\n");
  const fs::path periodic = write_ini("grow_periodic", ptext);
  const Result p = cli("run " + periodic.string() + " --quiet --out " + out.string());
  EXPECT_EQ(p.status, 0) << p.err;
  EXPECT_EQ(p.err.find("outermost"), std::string::npos) << p.err;
  fs::remove_all(out);
}

namespace {

// The unit sphere under the table F_z = F0 (1 + 0.3 sin 2 pi w t), F_x = 0.4 F0 cos 2 pi t
// (q = 0.8 at F0, mu = 0.5), 16 rows a period from t = -1/4 to 1, on a 32 x 32 grid.
Result run_varying_normal_table(const std::string& name, int w, const fs::path& out) {
  const double F0 = fretbem_test::unit_hertz_force();
  std::ofstream table(work_dir() / (name + ".csv"));
  table << std::setprecision(17) << "time,Fz,Fx\n";
  for (int k = -4; k <= 16; ++k) {
    const double t = k / 16.0;
    table << t << "," << F0 * (1 + 0.3 * std::sin(2 * M_PI * w * t)) << ","
          << 0.4 * F0 * std::cos(2 * M_PI * t) << "\n";
  }
  table.close();
  const fs::path ini =
      write_ini(name, fretbem_test::unit_sphere_ini(32, "path = table\ntable = " + name + ".csv",
                                                    "[solver]\nstiffness = false\n"));
  fs::remove_all(out);
  return cli("run " + ini.string() + " --out " + out.string());
}

// The turning rows of a run's timeseries.csv at which F_z rose over the step: each has no
// slipping node, and its step raised the bound faster than the tangential load
// (|dF_x| < mu dF_z, Mindlin-Deresiewicz: no slip anywhere). Returns how many there were.
int check_rising_peaks_stick(const fs::path& out) {
  auto ts = fretbem_test::csv_columns(out / "timeseries.csv");
  const std::vector<double>&fz = ts["Fz"], &fx = ts["Fx"], &slip = ts["slip_area"];
  int rising = 0;
  for (std::size_t k = 1; k < fz.size(); ++k)
    if (ts["turning"][k] == 1 && fz[k] > fz[k - 1]) {
      ++rising;
      EXPECT_LT(std::abs(fx[k] - fx[k - 1]), 0.5 * (fz[k] - fz[k - 1])) << "row " << k;
      EXPECT_EQ(slip[k], 0.0) << "row " << k;
    }
  return rising;
}

}  // namespace

// Under a normal load that rises at a tangential peak the whole contact sticks there at any
// grid, so that peak says nothing of the slip ring's resolution: one peak rising (w = 1) and one
// falling reports the falling peak's ring without "no node slips"; both rising (w = 2) reports
// full stick, without a warning.
TEST(SlipRing, PeaksReachedUnderARisingNormalLoadStickWithoutAWarning) {
  const fs::path out = work_dir() / "rising_run";
  const Result one = run_varying_normal_table("rising_one", 1, out);
  ASSERT_EQ(one.status, 0) << one.err;
  EXPECT_EQ(check_rising_peaks_stick(out), 2);  // t = 0 and 1
  EXPECT_EQ(one.err.find("no node slips"), std::string::npos) << one.err;
  EXPECT_NE(one.out.find("resolution: slip ring"), std::string::npos) << one.out;
  EXPECT_NE(one.out.find("full stick at peaks reached under a rising normal load"),
            std::string::npos)
      << one.out;
  const Result both = run_varying_normal_table("rising_both", 2, out);
  ASSERT_EQ(both.status, 0) << both.err;
  EXPECT_EQ(check_rising_peaks_stick(out), 3);  // t = 0, 1/2 and 1
  EXPECT_EQ(both.err.find("WARNING"), std::string::npos) << both.err;
  EXPECT_NE(both.out.find("resolution: no node slips at the load peaks, reached while the "
                          "normal load rises"),
            std::string::npos)
      << both.out;
  fs::remove_all(out);
}

namespace {

// The cycle (0, 1] of a table path sampled at quarters: F_x = +Q at t = 0 (the step before),
// -Q at t = 1/2 and +Q at t = 1 (turning points; slip areas 88 and 0, k_x 1 and 2), each
// extreme moved by `ulps` units in its last place (the round-off of a sum in another order).
CycleRow cycle_with_equal_peaks(int ulp_half, int ulp_end) {
  const double Q = 2.5;
  auto moved = [](double v, int ulps) {
    for (; ulps > 0; --ulps) v = std::nextafter(v, INFINITY);
    for (; ulps < 0; ++ulps) v = std::nextafter(v, -INFINITY);
    return v;
  };
  CycleAccumulator acc(PathType::table, 1.0);
  auto step = [&acc](int k, double t, double fx, bool turning, double slip, double kx) {
    StepRecord r;
    r.step = k, r.time = t, r.Fx = fx, r.turning = turning, r.slip_area = slip, r.kx = kx;
    return acc.add(r);
  };
  step(0, 0.0, Q, false, 0.0, 1.0);
  step(1, 0.25, 0.0, false, 10.0, 1.0);
  step(2, 0.5, moved(-Q, ulp_half), true, 88.0, 1.0);
  step(3, 0.75, 0.0, false, 10.0, 1.0);
  step(4, 1.0, moved(Q, ulp_end), true, 0.0, 2.0);
  return *acc.finish();
}

}  // namespace

// Two turning points of one |F_x| (a table's -Q and +Q rows) whose computed forces differ in
// their last bits, either way round, as the order of a sum (the ranks of a distributed grid)
// makes them: the cycle's peak is the first (slip area 88) and k_x at the largest F_x the last
// turning point, whatever the bits. A difference the path resolves still decides: +Q larger
// by 1e-6 makes t = 1 the peak.
TEST(CyclePeak, EqualLoadsPickTheSameTurningPointWhateverTheirLastBits) {
  for (int half : {-2, 0, 2})
    for (int end : {-2, 0, 2}) {
      const CycleRow c = cycle_with_equal_peaks(half, end);
      EXPECT_EQ(c.slip_area_at_peak, 88.0) << half << " " << end;
      EXPECT_EQ(c.kx_at_max, 2.0) << half << " " << end;
      EXPECT_EQ(c.kx_at_min, 1.0) << half << " " << end;
    }
  CycleAccumulator acc(PathType::table, 1.0);
  for (const auto& [k, t, fx, slip] : std::vector<std::tuple<int, double, double, double>>{
           {0, 0.0, 2.5, 0.0}, {1, 0.5, -2.5, 88.0}, {2, 1.0, 2.5 * (1 + 1e-6), 0.0}}) {
    StepRecord r;
    r.step = k, r.time = t, r.Fx = fx, r.turning = k > 0, r.slip_area = slip;
    acc.add(r);
  }
  EXPECT_EQ(acc.finish()->slip_area_at_peak, 0.0);
}
