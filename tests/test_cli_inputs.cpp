// `check` and `run` judge inputs alike: the same refusals with the same line and exit code,
// the same warnings for keys that change nothing, one full-sliding shift U*, the small-slip
// bound on shifts; `surface` refuses the heights they refuse.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "fretbem/elastic/closed_forms.hpp"
#include "support/cli.hpp"

namespace fs = std::filesystem;

namespace {

using Result = fretbem_test::CliResult;

Result cli(const std::string& args) {
  return fretbem_test::run_fretbem(args, "fretbem_cli_inputs_test");
}

std::string scenario(const std::string& name) {
  return (fs::path(FRETBEM_SOURCE_DIR) / "scenarios" / name).string();
}

fs::path scratch(const std::string& name) {
  return fretbem_test::process_temp_dir().vacant(name);
}

int count(const std::string& s, const std::string& what) {
  int n = 0;
  for (auto p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
  return n;
}

// hertz.ini at n = 32 (a = 68.75 um = 7.9 cells): quick to run.
const std::string kHertz = " --set grid.n=32 --quiet";

// The mindlin_cycle sphere (E = 210 GPa, nu = 0.3, R = 10 mm, Fz = 10 N, mu = 0.5) under a
// displacement-controlled sine; its closed forms below.
std::string exact(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

std::string displacement_sine(double amplitude) {
  return scenario("mindlin_cycle.ini") +
         " --set grid.n=32 --set load.control=displacement"
         " --set load.cycles=1 --set load.steps_per_cycle=8 --set load.displacement_amplitude=" +
         exact(amplitude) + " --out " + scratch("sine").string();
}

struct Hertz {
  double a = 0, ustar = 0;
};

// Johnson eqs. 4.22-4.23 and Mindlin's full-sliding shift U* = mu delta E*/G*, rigid sphere.
Hertz mindlin_sphere() {
  const double E = 210e9, nu = 0.3, R = 0.01, F = 10, mu = 0.5;
  const double E_star = E / (1 - nu * nu), G = E / (2 * (1 + nu));
  const double G_star = 4 * G / (2 - nu);
  Hertz h;
  h.a = fretbem::closed_forms::hertz_contact_radius(F, R, E_star);
  h.ustar = fretbem::closed_forms::full_sliding_shift(
      mu, fretbem::closed_forms::hertz_approach(h.a, R), E_star, G_star);
  return h;
}

double number_after(const std::string& text, const std::string& label) {
  const auto p = text.find(label);
  if (p == std::string::npos) return std::nan("");
  return std::stod(text.substr(p + label.size()));
}

}  // namespace

// Keys that change nothing under the scenario's choices: one warning line each, on stderr,
// from check and run alike, naming the key and the condition under which it is read.
TEST(CliInputs, KeysThatChangeNothingAreWarnedByCheckAndRun) {
  const std::string keys[] = {"wear.coefficient", "wear.cycles",        "friction.mu_kinetic",
                              "friction.scale",   "surface.hurst",      "surface.seed",
                              "load.direction",   "output.fields_every"};
  const std::string sets =
      " --set wear.coefficient=1e-14 --set wear.cycles=100 --set friction.mu_kinetic=0.3"
      " --set friction.scale=1 --set surface.hurst=0.5 --set surface.seed=3"
      " --set load.direction=30 --set output.fields=none --set output.fields_every=5";
  const fs::path out = scratch("ignored");
  const Result check = cli("check " + scenario("hertz.ini") + kHertz + sets +
                           " --no-estimate --out " + scratch("ignored_check").string());
  const Result run = cli("run " + scenario("hertz.ini") + kHertz + sets + " --out " + out.string());
  ASSERT_EQ(check.status, 0) << check.err;
  ASSERT_EQ(run.status, 0) << run.err;
  for (const auto& key : keys)
    for (const Result* r : {&check, &run})
      EXPECT_EQ(count(r->err, "fretbem: warning: " + key + " is ignored: "), 1) << key << r->err;
  EXPECT_NE(check.err.find("read only in a wear run (here wear.law = none)"), std::string::npos);
  EXPECT_NE(check.err.find("read only with surface.type = rough (here sphere)"), std::string::npos);
  // A scenario whose keys all take effect draws no warning.
  EXPECT_EQ(cli("check " + scenario("hertz.ini") + kHertz + " --no-estimate --out " +
                scratch("clean").string())
                .err,
            "");
}

// What run refuses before its tangential solves, check refuses with the same line and code:
// a radius typed in mm (10 for 10 mm) makes a Hertz contact larger than the domain.
TEST(CliInputs, CheckRefusesRunsRefusalWithTheSameLine) {
  const std::string mm =
      scenario("mindlin_cycle.ini") + " --set grid.n=32 --set surface.radius=10 --out ";
  const Result run = cli("run " + mm + scratch("mm_run").string() + " --quiet");
  const Result check = cli("check " + mm + scratch("mm_check").string());
  const Result quick = cli("check " + mm + scratch("mm_quick").string() + " --no-estimate");
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.err.find("grid.allow_edge_contact"), std::string::npos) << run.err;
  for (const Result* r : {&check, &quick}) {
    EXPECT_EQ(r->status, 2);
    EXPECT_EQ(r->err, run.err);
  }
}

// check takes run's --out and --overwrite, so it refuses a folder holding a run's results.
TEST(CliInputs, CheckRefusesAnOutputFolderRunRefuses) {
  const fs::path out = scratch("taken");
  const std::string hertz = scenario("hertz.ini") + kHertz + " --out " + out.string();
  ASSERT_EQ(cli("run " + hertz).status, 0);
  const Result run = cli("run " + hertz);
  const Result check = cli("check " + hertz + " --no-estimate");
  EXPECT_EQ(run.status, 2);
  EXPECT_EQ(check.status, 2);
  EXPECT_EQ(check.err, run.err);
  EXPECT_EQ(cli("check " + hertz + " --no-estimate --overwrite").status, 0);
}

// One U*: what check prints and what the refusal of a shift past 1e6 U* quotes, both Mindlin's
// mu delta E*/G* at the Hertz approach (not the sphere's height range over the domain).
TEST(CliInputs, CheckAndTheShiftRefusalQuoteOneFullSlidingShift) {
  const Hertz h = mindlin_sphere();
  const Result check = cli("check " + displacement_sine(1e-6) + " --no-estimate");
  ASSERT_EQ(check.status, 0) << check.err;
  const double printed = number_after(check.out, "U* = mu delta E*/G* = ");
  EXPECT_NEAR(printed, h.ustar, 1e-3 * h.ustar) << check.out;  // printed to 4 digits
  const Result refused = cli("check " + displacement_sine(10.0) + " --no-estimate");
  ASSERT_EQ(refused.status, 2);
  const double quoted = number_after(refused.err, "U* = mu delta E*/G* = ");
  EXPECT_NEAR(quoted, h.ustar, 1e-12 * h.ustar) << refused.err;
}

// The model keeps the contact geometry fixed: a shift past one contact radius is refused
// unless load.allow_large_shift = true, one past a quarter of it warned about.
TEST(CliInputs, ShiftsAreBoundedByTheContactRadius) {
  const Hertz h = mindlin_sphere();
  const Result small = cli("check " + displacement_sine(0.2 * h.a) + " --no-estimate");
  EXPECT_EQ(small.status, 0);
  EXPECT_EQ(small.err.find("contact radius"), std::string::npos) << small.err;
  const Result half = cli("check " + displacement_sine(0.5 * h.a) + " --no-estimate");
  EXPECT_EQ(half.status, 0);
  EXPECT_EQ(count(half.err, "warning: load.displacement_amplitude"), 1) << half.err;
  const Result far = cli("check " + displacement_sine(1.5 * h.a) + " --no-estimate");
  EXPECT_EQ(far.status, 2);
  EXPECT_NE(far.err.find("load.allow_large_shift"), std::string::npos) << far.err;
  const Result run = cli("run " + displacement_sine(1.5 * h.a) + " --quiet");
  EXPECT_EQ(run.status, 2);
  EXPECT_EQ(run.err, far.err);
  const Result allowed = cli("check " + displacement_sine(1.5 * h.a) +
                             " --set load.allow_large_shift=true --no-estimate");
  EXPECT_EQ(allowed.status, 0) << allowed.err;
  EXPECT_EQ(count(allowed.err, "warning: load.displacement_amplitude"), 1) << allowed.err;
}

// `fretbem surface` refuses heights past 1e100 m as check and run do, and writes no file.
TEST(CliInputs, SurfaceRefusesHeightsCheckAndRunRefuse) {
  const fs::path map = fs::path(FRETBEM_SOURCE_DIR) / "tests/bad_inputs/surfaces/heights_1e150.npy";
  const std::string driver =
      (fs::path(FRETBEM_SOURCE_DIR) / "tests/bad_inputs/surfaces/driver.ini").string();
  const fs::path out = scratch("huge") / "copy.npy";
  fs::create_directories(out.parent_path());
  const Result surface =
      cli("surface " + driver + " --set surface.file=" + map.string() + " --out " + out.string());
  const Result check = cli("check " + driver + " --set surface.file=" + map.string() + " --out " +
                           scratch("huge_check").string());
  EXPECT_EQ(surface.status, 2);
  EXPECT_EQ(surface.err, check.err);
  EXPECT_NE(surface.err.find("1e+150"), std::string::npos) << surface.err;
  EXPECT_FALSE(fs::exists(out));
}

// check describes a loaded height map: shape, range, rms and where its spacing comes from.
TEST(CliInputs, CheckDescribesALoadedHeightMap) {
  const std::string driver =
      (fs::path(FRETBEM_SOURCE_DIR) / "tests/bad_inputs/surfaces/driver.ini").string();
  const fs::path map = scratch("map") / "map.txt";
  fs::create_directories(map.parent_path());
  std::ofstream(map)
      << "0 0 0 0\n0 2e-7 0 0\n0 0 0 0\n0 0 0 0\n";  // one bump, rms sqrt(15)/16 x 2e-7
  const std::string base = "check " + driver + " --no-estimate --set surface.file=" + map.string() +
                           " --out " + scratch("map_check").string();
  const Result plain = cli(base);
  ASSERT_EQ(plain.status, 0) << plain.err;
  EXPECT_NE(plain.out.find("4 x 4 (x by y), heights 0 .. 2e-07 m, rms 4.841e-08 m"),
            std::string::npos)
      << plain.out;
  EXPECT_NE(plain.err.find("carries no spacing and surface.spacing is not given"),
            std::string::npos)
      << plain.err;
  const Result stated = cli(base + " --set surface.spacing=7e-5");
  ASSERT_EQ(stated.status, 0) << stated.err;
  EXPECT_NE(stated.out.find("(surface.spacing, checked against grid.length / n)"),
            std::string::npos)
      << stated.out;
  EXPECT_EQ(stated.err, "");
}

// A [vary] list with a trailing comma is refused as one with an empty item inside, naming the
// study file and the key.
TEST(CliInputs, SweepListsRefuseTrailingAndInnerEmptyItems) {
  const fs::path dir = scratch("study");
  fs::create_directories(dir);
  for (const std::string list : {"0.2, 0.4,", "0.2, , 0.4"}) {
    const fs::path study = dir / "study.ini";
    std::ofstream(study) << "[study]\nscenario = " << scenario("mindlin_cycle.ini")
                         << "\n[vary]\nload.amplitude = " << list << "\n";
    const Result r = cli("sweep " + study.string() + " --list");
    EXPECT_EQ(r.status, 2) << list;
    EXPECT_NE(r.err.find(study.string()), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("load.amplitude"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("empty value"), std::string::npos) << r.err;
  }
}
