// Scenario reading: SI values, defaults, overrides, path resolution, and one-line InputErrors
// that name the key for every kind of bad input.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "fretbem/core/errors.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/scenario/ignored_keys.hpp"
#include "fretbem/scenario/scenario.hpp"
#include "support/temp_dir.hpp"

namespace fs = std::filesystem;
using fretbem::InputError;
using fretbem::parse_scenario;
using fretbem::Scenario;
using fretbem_test::TempDir;

namespace {

void write_file(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary) << text;
}

const std::string kGood = R"(# a Cattaneo ramp
[material]
E = 210e9      # steel
nu = 0.3
mu = 0.5

[grid]
n = 64
length = 2e-3

[surface]
type = sphere
radius = 0.01

[load]
normal_force = 100
path = ramp
amplitude = 0.95
steps = 20

[solver]
tolerance = 1e-8
coupling = cerruti
threads = 2
stiffness = no

[output]
fields = pressure, state
)";

Scenario parse(const std::string& text, const std::vector<std::string>& overrides = {}) {
  return parse_scenario(text, "test.ini", fs::temp_directory_path(), overrides);
}

/// The InputError message of parsing text with overrides (fails the test if none is thrown).
std::string error_of(const std::string& text, const std::vector<std::string>& overrides = {}) {
  try {
    parse(text, overrides);
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "message is not one line: " << msg;
    return msg;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an InputError: " << e.what();
    return {};
  }
  ADD_FAILURE() << "no error for overrides of " << text.substr(0, 60);
  return {};
}

std::string with(const std::string& key_value) {
  return error_of(kGood, {key_value});
}

#define EXPECT_HAS(msg, part) EXPECT_NE((msg).find(part), std::string::npos) << (msg)

}  // namespace

TEST(Scenario, GoodFileGivesSIValuesAndDefaults) {
  const Scenario s = parse(kGood);
  EXPECT_EQ(s.name, "test");
  EXPECT_DOUBLE_EQ(s.material.body1.E, 210e9);
  EXPECT_DOUBLE_EQ(s.material.body1.nu, 0.3);
  EXPECT_FALSE(s.material.body2.has_value());
  EXPECT_DOUBLE_EQ(s.material.mu, 0.5);
  EXPECT_EQ(s.grid.nx, 64);
  EXPECT_EQ(s.grid.ny, 64);
  EXPECT_DOUBLE_EQ(s.grid.h, 2e-3 / 64);
  EXPECT_FALSE(s.grid.periodic);
  EXPECT_EQ(s.surface.type, fretbem::SurfaceType::sphere);
  EXPECT_DOUBLE_EQ(s.surface.radius, 0.01);
  ASSERT_TRUE(s.load.normal_force.has_value());
  EXPECT_DOUBLE_EQ(*s.load.normal_force, 100.0);
  EXPECT_FALSE(s.load.indentation.has_value());
  EXPECT_EQ(s.load.path, fretbem::PathType::ramp);
  EXPECT_EQ(s.load.control, fretbem::Control::force);
  EXPECT_DOUBLE_EQ(s.load.amplitude, 0.95);
  EXPECT_EQ(s.load.steps, 20);
  EXPECT_EQ(s.load.cycles, 1);
  EXPECT_DOUBLE_EQ(s.solver.tolerance, 1e-8);
  EXPECT_EQ(s.solver.coupling, fretbem::Coupling::cerruti);
  EXPECT_EQ(s.solver.threads, 2);
  EXPECT_EQ(s.solver.stiffness, fretbem::StiffnessMode::none);
  EXPECT_EQ(s.solver.max_iterations, 5000);
  EXPECT_EQ(s.output.fields, (std::vector<std::string>{"pressure", "state"}));
  EXPECT_EQ(s.output.dir, fs::path("out"));
  EXPECT_EQ(s.wear.law, fretbem::WearLaw::none);
}

TEST(Scenario, SecondBodyNonSquareGridRoughAndWear) {
  const Scenario s = parse(R"(
[material]
E = 1e9
nu = 0
E2 = 2e9
nu2 = 0.25
[grid]
nx = 64
ny = 32
length = 1e-3
periodic = yes
[surface]
type = rough
hurst = 0.7
rms_slope = 0.1
method = fourier
seed = 18446744073709551615
cutoff_wavelength = 1e-5
rolloff_wavelength = 1e-4
[load]
indentation = 1e-6
path = sine
control = displacement
displacement_amplitude = 2e-7
cycles = 3
steps_per_cycle = 16
direction = 45
[wear]
law = energy
coefficient = 1e-9
cycles = 1e5
)");
  ASSERT_TRUE(s.material.body2.has_value());
  EXPECT_DOUBLE_EQ(s.material.body2->nu, 0.25);
  EXPECT_EQ(s.grid.nx, 64);
  EXPECT_EQ(s.grid.ny, 32);
  EXPECT_DOUBLE_EQ(s.grid.h, 1e-3 / 64);
  EXPECT_TRUE(s.grid.periodic);
  EXPECT_EQ(s.surface.rough.method, fretbem::RoughMethod::fourier);
  EXPECT_EQ(s.surface.rough.seed, 18446744073709551615ull);
  EXPECT_DOUBLE_EQ(*s.surface.rough.rms_slope, 0.1);
  EXPECT_FALSE(s.surface.rough.rms_height.has_value());
  EXPECT_EQ(s.load.control, fretbem::Control::displacement);
  EXPECT_DOUBLE_EQ(s.load.direction, 45.0);
  EXPECT_EQ(s.wear.law, fretbem::WearLaw::energy);
  EXPECT_DOUBLE_EQ(s.wear.cycles, 1e5);
}

TEST(Scenario, OverridesWinAndAddKeys) {
  const Scenario s = parse(kGood, {"grid.n=32", "material.mu = 0.25", "grid.periodic=true",
                                   "solver.fft_plan=measure", "grid.n=16"});
  EXPECT_EQ(s.grid.nx, 16);  // the last override of a key wins
  EXPECT_DOUBLE_EQ(s.grid.h, 2e-3 / 16);
  EXPECT_DOUBLE_EQ(s.material.mu, 0.25);
  EXPECT_TRUE(s.grid.periodic);
  EXPECT_EQ(s.solver.fft_plan, fretbem::FftPlanning::measure);
  EXPECT_EQ(s.solver.precondition, fretbem::Precondition::automatic);
  EXPECT_EQ(parse(kGood, {"solver.precondition=off"}).solver.precondition,
            fretbem::Precondition::off);
  const Scenario on = parse(kGood, {"solver.precondition=on"});
  EXPECT_EQ(on.solver.precondition, fretbem::Precondition::on);
  EXPECT_EQ(parse(on.resolved_text).solver.precondition, fretbem::Precondition::on);
  EXPECT_HAS(error_of(kGood, {"solver.precondition=maybe"}), "solver.precondition");
}

TEST(Scenario, ResolvedTextReproducesTheScenario) {
  const Scenario s = parse(kGood, {"load.direction=12.345678901234567"});
  const Scenario again = parse(s.resolved_text);
  EXPECT_EQ(again.resolved_text, s.resolved_text);
  EXPECT_EQ(again.load.direction, 12.345678901234567);
  EXPECT_EQ(again.material.body1.E, 210e9);
  EXPECT_EQ(again.grid.h, s.grid.h);
  for (const char* key :
       {"E = ", "mu = ", "n = ", "length = ", "periodic = ", "type = ", "tolerance = ",
        "max_iterations = ", "fields = pressure, state", "law = none", "# indentation = (unset)"})
    EXPECT_HAS(s.resolved_text, key);
}

TEST(Scenario, ExactMessageFormats) {
  EXPECT_EQ(with("material.nu=0.7"), "--set material.nu=0.7: out of range [0, 0.5)");
  EXPECT_EQ(error_of("[material]\nE=1\nnu=0.7\n"),
            "test.ini: material.nu = 0.7 is out of range [0, 0.5)");
  EXPECT_EQ(error_of(kGood + "[material]\nmue = 0.3\n"),
            "test.ini: unknown key 'material.mue' (did you mean 'material.mu'?)");
  EXPECT_EQ(with("grid.n=abc"), "--set grid.n=abc: not an integer");
}

TEST(Scenario, UnknownNamesSuggestTheNearest) {
  EXPECT_HAS(error_of(kGood + "[grid]\nmu = 0.3\n"), "(did you mean 'material.mu'?)");
  EXPECT_HAS(with("load.normal force=3"), "did you mean 'load.normal_force'");
  EXPECT_HAS(with("material.e=3"), "did you mean 'material.E'");
  EXPECT_HAS(with("material.NU=0.3"), "did you mean 'material.nu'");
  EXPECT_HAS(with("output.fields=pressure,tracton_x"), "did you mean 'traction_x'");
  const std::string far = with("solver.zzzzzzzzzzzz=1");
  EXPECT_HAS(far, "unknown key 'solver.zzzzzzzzzzzz'");
  EXPECT_EQ(far.find("did you mean"), std::string::npos) << far;
}

// Some editors start UTF-8 files with a byte-order mark; it is not part of the first line.
TEST(Scenario, ByteOrderMarkIsSkipped) {
  const Scenario s = parse("\xEF\xBB\xBF" + kGood);
  EXPECT_EQ(s.material.body1.E, parse(kGood).material.body1.E);
}

// Dimensional inputs outside 1e-100..1e100 name the key (value_reader.hpp).
TEST(Scenario, MagnitudesTheArithmeticCannotCarryNameTheKey) {
  for (const char* kv : {"material.E=1e-300", "material.E=1e308", "grid.length=1e200",
                         "surface.radius=1e-300", "load.normal_force=1e101"}) {
    EXPECT_HAS(with(kv), "outside [1e-100, 1e100]");
    EXPECT_HAS(with(kv), kv);
  }
  EXPECT_HAS(with("wear.cycles=0.5"), "wear.cycles");
}

TEST(Scenario, StructuralErrors) {
  EXPECT_HAS(error_of(kGood + "[materials]\nE = 1\n"), "unknown section [materials]");
  EXPECT_HAS(error_of(kGood + "[materials]\nE = 1\n"), "(did you mean 'material'?)");
  const std::string foo = error_of(kGood + "[foo]\nbar = 1\n");
  EXPECT_HAS(foo, "unknown section [foo]");
  EXPECT_HAS(foo, "(sections: material, grid");
  EXPECT_HAS(error_of("E = 1\n" + kGood), "key 'E' is outside any section");
  EXPECT_HAS(error_of(kGood + "[material]\nmu = 0.6\n"), "duplicated key 'material.mu'");
  EXPECT_HAS(error_of(kGood + "just words\n"), "test.ini: ");
  EXPECT_HAS(with("grid.n"), "--set grid.n: expected section.key=value");
  EXPECT_HAS(with("=3"), "expected section.key=value");
  EXPECT_HAS(with("grid.q=3"), "unknown key 'grid.q'");
  EXPECT_HAS(error_of(""), "missing required key 'material.E'");
}

TEST(Scenario, FileNotFound) {
  const fs::path missing = fs::temp_directory_path() / "fretbem_no_such_dir" / "x.ini";
  try {
    fretbem::load_scenario(missing);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_HAS(std::string(e.what()), missing.string());
    EXPECT_HAS(std::string(e.what()), "not found");
  }
}

TEST(Scenario, BadNumbersNameTheKey) {
  for (const char* v : {"nan", "NaN", "inf", "-inf", "1e999", "", "abc", "1e3 Pa", "0x10", "--1",
                        "1,5", "-1", "0"}) {
    const std::string msg = with(std::string("material.E=") + v);
    EXPECT_HAS(msg, "material.E");
  }
  EXPECT_HAS(with("material.E=1e999"), "out of the range of a double");
  EXPECT_HAS(with("material.E=nan"), "not a finite number");
  EXPECT_HAS(with("material.E=-1"), "must be > 0");
  EXPECT_HAS(with("grid.n=1"), "must be >= 2");
  EXPECT_HAS(with("grid.n=99999999999999999999999"), "grid.n");
  EXPECT_HAS(with("grid.n=1000000"), "out of range [2, 65536]");
  EXPECT_HAS(with("grid.n=2.5"), "not an integer");
  EXPECT_HAS(with("grid.periodic=maybe"), "not a boolean");
  EXPECT_HAS(with("surface.type=cube"), "not one of sphere|flat|rough|file");
  EXPECT_HAS(with("solver.tolerance=0.1"), "out of range [1e-14, 0.01]");
  EXPECT_HAS(with("solver.tolerance=1e-300"), "out of range [1e-14, 0.01]");
  EXPECT_HAS(with("solver.threads=-1"), "solver.threads");
  EXPECT_HAS(with("load.steps_per_cycle=3"), "must be >= 4");
  EXPECT_HAS(with("output.fields_every=-2"), "output.fields_every");
  EXPECT_HAS(with("surface.seed=-1"), "surface.seed");
  EXPECT_HAS(with("surface.hurst=1.5"), "surface.hurst");
  EXPECT_HAS(with("output.fields=pressure,velocity"), "unknown field 'velocity'");
}

TEST(Scenario, CrossKeyRules) {
  EXPECT_HAS(with("material.E2=1e9"), "material.E2 and material.nu2");
  EXPECT_HAS(error_of("[material]\nE=1\nnu=0.3\n"), "missing required key 'grid.n'");
  EXPECT_HAS(error_of("[material]\nE=1\nnu=0.3\n[grid]\nnx=4\n"), "grid.n");
  EXPECT_HAS(error_of("[material]\nE=1\nnu=0.3\n[grid]\nn=4\n"), "grid.length");
  EXPECT_HAS(with("surface.radius=0"), "surface.radius");
  EXPECT_HAS(error_of(kGood, {"load.indentation=1e-6"}), "load.normal_force and load.indentation");
  const std::string no_load = R"([material]
E=1
nu=0.3
[grid]
n=8
length=1
[surface]
type=flat
)";
  EXPECT_HAS(error_of(no_load), "load.normal_force");
  EXPECT_HAS(error_of(no_load + "[load]\nindentation=1\npath=sine\n"), "load.amplitude");
  EXPECT_HAS(with("surface.type=rough"), "surface.rms_height");
  EXPECT_HAS(error_of(kGood, {"surface.type=rough", "surface.rms_height=1e-6"}), "surface.seed");
  EXPECT_HAS(error_of(kGood, {"surface.type=rough", "surface.rms_height=1e-6",
                              "surface.rms_slope=0.1", "surface.seed=1"}),
             "exactly one");
  EXPECT_HAS(error_of(kGood, {"surface.type=rough", "surface.rms_height=1e-6", "surface.seed=1",
                              "surface.cutoff_wavelength=1e-3", "surface.rolloff_wavelength=1e-4"}),
             "surface.cutoff_wavelength");
  EXPECT_HAS(with("surface.type=file"), "surface.file");
  EXPECT_HAS(with("load.path=table"), "load.table");
  EXPECT_HAS(with("wear.law=archard"), "wear.coefficient");
  EXPECT_HAS(error_of(kGood, {"wear.law=archard", "wear.coefficient=1e-15"}), "wear.cycles");
  EXPECT_HAS(error_of(kGood, {"wear.law=archard", "wear.coefficient=1e-15", "wear.cycles=10.5",
                              "wear.integrator=cycle"}),
             "whole number");
  EXPECT_HAS(with("load.control=displacement"), "load.displacement_amplitude");
}

TEST(Scenario, ImpossibleForceAmplitudeIsExplained) {
  const std::string msg = with("load.amplitude=1");
  EXPECT_HAS(msg, "load.amplitude");
  EXPECT_HAS(msg, "impossible");
  EXPECT_HAS(msg, "mu Fz");
  EXPECT_HAS(with("load.amplitude=0"), "load.amplitude");
  EXPECT_HAS(with("load.amplitude=-0.5"), "load.amplitude");
  // Displacement control may slide grossly; the force amplitude is then not used.
  EXPECT_NO_THROW(parse(kGood, {"load.control=displacement", "load.displacement_amplitude=1e-6",
                                "load.amplitude=2"}));
}

TEST(Scenario, RelativePathsResolveAgainstTheScenarioFolder) {
  const TempDir tmp("scenario");
  const fs::path dir = tmp.path() / "cases";
  write_file(dir / "maps" / "z.txt", "0 1\n2 3\n");
  write_file(dir / "path.csv", "time,Fz,Fx\n0,1,0\n1,1,0.5\n");
  write_file(dir / "rough.ini", R"([material]
E = 1e9
nu = 0.3
[grid]
n = 2
length = 1e-3
[surface]
type = file
file = maps/z.txt
[load]
path = table
table = path.csv
)");
  const Scenario s = fretbem::load_scenario(dir / "rough.ini");
  EXPECT_EQ(s.name, "rough");
  EXPECT_TRUE(s.surface.file.is_absolute());
  EXPECT_TRUE(fs::equivalent(s.surface.file, dir / "maps" / "z.txt"));
  EXPECT_TRUE(fs::equivalent(s.load.table, dir / "path.csv"));
  EXPECT_HAS(s.resolved_text, (dir / "maps" / "z.txt").lexically_normal().string());

  auto load_error = [&](const std::vector<std::string>& overrides) {
    try {
      fretbem::load_scenario(dir / "rough.ini", overrides);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_HAS(load_error({"surface.file=maps/missing.txt"}), "--set surface.file=maps/missing.txt");
  EXPECT_HAS(load_error({"load.table=nope.csv"}), "load.table");
  write_file(dir / "bad.csv", "time,Fz,Fq\n");
  EXPECT_HAS(load_error({"load.table=bad.csv"}), "unknown column 'Fq'");
  write_file(dir / "no_normal.csv", "time,Fx\n0,0\n");
  EXPECT_HAS(load_error({"load.table=no_normal.csv"}), "neither Fz nor delta");
  EXPECT_NO_THROW(fretbem::load_scenario(dir / "rough.ini",
                                         {"load.table=no_normal.csv", "load.normal_force=2"}));
  EXPECT_HAS(load_error({"load.control=displacement"}), "Fx/Fy columns");
}

TEST(Scenario, JunkNeverCrashes) {
  std::mt19937 rng(12345);
  const std::string alphabet = "[]=#.\n\t ab01e-+\x01\xff\x80materialgridn";
  for (int trial = 0; trial < 300; ++trial) {
    std::string text;
    const int len = static_cast<int>(rng() % 200);
    for (int k = 0; k < len; ++k) {
      text += (trial % 2) ? static_cast<char>(rng() % 256) : alphabet[rng() % alphabet.size()];
    }
    try {
      parse(text);
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    }
    try {
      parse(kGood, {text});
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    }
  }
}

// surface.spacing and load.allow_large_shift are read, bounded like every dimensional input,
// and written to the resolved scenario.
TEST(Scenario, SpacingAndLargeShiftKeys) {
  const Scenario s = parse(kGood, {"surface.spacing=3.125e-5", "load.allow_large_shift=yes"});
  ASSERT_TRUE(s.surface.spacing);
  EXPECT_EQ(*s.surface.spacing, 3.125e-5);
  EXPECT_TRUE(s.load.allow_large_shift);
  const Scenario again = parse(s.resolved_text);
  EXPECT_EQ(*again.surface.spacing, 3.125e-5);
  EXPECT_TRUE(again.load.allow_large_shift);
  EXPECT_HAS(parse(kGood).resolved_text, "# spacing = (unset)");
  EXPECT_HAS(with("surface.spacing=1e300"), "[1e-100, 1e100]");
  EXPECT_HAS(with("load.allow_large_shift=maybe"), "not a boolean");
}

// Every key of the conditional-key table is a scenario key: a bad value draws that key's own
// message or none, never "unknown key" (a misspelt table entry would warn about nothing).
TEST(Scenario, IgnoredKeyTableNamesRealKeys) {
  const auto keys = fretbem::conditional_keys();
  EXPECT_GE(keys.size(), 30u);
  for (const auto& key : keys) try {
      parse(kGood, {key + "=@@"});  // free text (surface.dataset) may pass
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).find("unknown"), std::string::npos)
          << key << ": " << e.what();
    }
}

// Each key the scenario's choices leave unread is named once with its condition; kGood (a
// force-controlled sphere ramp) reads all of its own keys.
TEST(Scenario, IgnoredKeysFollowTheScenarioChoices) {
  EXPECT_TRUE(fretbem::ignored_keys(parse(kGood)).empty());
  const auto ignored = fretbem::ignored_keys(parse(
      kGood, {"surface.seed=4", "load.cycles=3", "load.displacement_amplitude=1e-6",
              "wear.indenter_share=0.5", "solver.coupling_iterations=7", "surface.spacing=1e-6"}));
  std::vector<std::string> keys;
  for (const auto& k : ignored) keys.push_back(k.key);
  EXPECT_EQ(keys, (std::vector<std::string>{"surface.seed", "surface.spacing",
                                            "load.displacement_amplitude", "load.cycles",
                                            "solver.coupling_iterations", "wear.indenter_share"}));
  // The same key is read once the scenario chooses what reads it.
  EXPECT_TRUE(fretbem::ignored_keys(parse(kGood, {"surface.type=rough", "surface.hurst=0.7",
                                                  "surface.rms_height=1e-6", "surface.seed=4"}))
                  .size() == 1);  // surface.radius, now on a rough surface
}

// A rough surface with no wavelength left to scale names the keys that decide it.
TEST(Scenario, ZeroRoughnessNamesTheKeys) {
  const Scenario s =
      parse(kGood, {"surface.type=rough", "surface.hurst=0.7", "surface.rms_height=1e-6",
                    "surface.seed=4", "surface.method=fourier", "surface.cutoff_wavelength=0.01"});
  try {
    fretbem::make_surface(s);
    ADD_FAILURE() << "a cut-off longer than the domain left roughness";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_HAS(msg, "surface.cutoff_wavelength = 0.01 m");
    EXPECT_HAS(msg, "grid.length = 0.002 m");
    EXPECT_HAS(msg, "64 x 64");
    EXPECT_HAS(msg, "surface.rms_height");
  }
}
