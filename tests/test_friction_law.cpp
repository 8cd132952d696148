// Friction laws against closed forms: a static/kinetic law's first slip is
// Cattaneo's with mu_s; after gross sliding a law that has moved mu uniformly reproduces the
// constant-mu solution with the new mu; a sliding contact carries mu_k F_z.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "fretbem/core/errors.hpp"
#include "support/hertz.hpp"

using namespace fretbem;
namespace fs = std::filesystem;

namespace {

// Hertz sphere, E = 1, nu = 0.3, R = 1, a = 1/4 on a unit domain.
const double kP = fretbem_test::unit_hertz_force();

std::string sphere(int n, double mu, const std::string& load, const std::string& friction) {
  return fretbem_test::unit_sphere_ini(n, "normal_force = " + format_number(kP) + "\n" + load,
                                       "[solver]\ntolerance = 1e-10\n[friction]\n" + friction, mu);
}

std::vector<StepRecord> run(const std::string& text) {
  return fretbem_test::run_steps(text, "friction");
}

// u* = mu delta E*/G*, delta = a^2 / R: the full-sliding shift for this mu.
double full_sliding_shift(double mu) {
  Material m;
  m.body1 = {1.0, 0.3};
  return mu * 0.0625 * m.E_star() / m.G_star();
}

fs::path shift_table(const std::vector<double>& ux) {
  const fs::path f =
      fs::temp_directory_path() / ("fretbem_friction_" + std::to_string(getpid()) + ".csv");
  std::ofstream out(f);
  out.precision(17);
  out << "time,Ux\n";
  for (std::size_t k = 0; k < ux.size(); ++k) out << k << "," << ux[k] << "\n";
  return f;
}

}  // namespace

// One increment to Q = 0.6 mu_s P from the virgin state: every node is stuck at its start, so
// the bound is mu_s p and the answer is Cattaneo's with mu_s (c/a = (1 - Q/mu_s P)^(1/3)):
// the rows equal the constant-mu run's, whatever mu_k.
TEST(FrictionLaw, StaticKineticFirstSlipIsCattaneoWithMuStatic) {
  const std::string load = "path = ramp\ncontrol = force\namplitude = 0.6\nsteps = 1";
  const auto sk = run(sphere(64, 0.5, load, "law = static_kinetic\nmu_kinetic = 0.35\n"));
  const auto c = run(sphere(64, 0.5, load, "law = constant\n"));
  ASSERT_EQ(sk.size(), 2u);
  EXPECT_EQ(sk[1].Fx, c[1].Fx);
  EXPECT_EQ(sk[1].Ux, c[1].Ux);
  EXPECT_EQ(sk[1].stick_area, c[1].stick_area);
  // Cattaneo: stick radius (1 - 0.6)^(1/3) a, within a cell of a = 16 cells.
  const double cells = std::sqrt(sk[1].stick_area / M_PI) * 64;
  EXPECT_NEAR(cells, 16 * std::cbrt(0.4), 1.0);
}

// Displacement control far past sliding: once every node slides, a static/kinetic contact
// carries mu_k F_z, and an evolving mu (slip path, scale 1e-3 u*) reaches mu_final everywhere,
// after which its rows equal those of constant mu = mu_final (a uniform mu change reproduces
// the constant-mu solution with the new mu), reversals included.
TEST(FrictionLaw, UniformChangeReproducesConstantMu) {
  const double u = full_sliding_shift(0.6);
  const fs::path table = shift_table({0, 3 * u, 6 * u, 4 * u, 2 * u, 0, 3 * u});
  // Gross sliding to 6 u*, past the contact radius: the friction laws, not the small-slip
  // geometry, are under test.
  const std::string load = "path = table\ncontrol = displacement\nallow_large_shift = true\ntable = " +
                           table.string();
  std::ostringstream evolving;
  evolving << "law = evolving\nmu_final = 0.6\nevolution = slip_path\nscale = " << 1e-3 * u << "\n";
  const auto ev = run(sphere(48, 0.3, load, evolving.str()));
  const auto c = run(sphere(48, 0.6, load, "law = constant\n"));
  const auto sk = run(sphere(48, 0.6, load, "law = static_kinetic\nmu_kinetic = 0.4\n"));
  fs::remove(table);
  ASSERT_EQ(ev.size(), c.size());
  EXPECT_NEAR(ev[1].Fx, 0.3 * kP, 1e-8 * kP);  // first sliding step: mu_0
  for (std::size_t k = 2; k < c.size(); ++k) {
    EXPECT_NEAR(ev[k].Fx, c[k].Fx, 1e-8 * kP) << "row " << k;
    EXPECT_EQ(ev[k].stick_area, c[k].stick_area) << "row " << k;
  }
  EXPECT_NEAR(sk[2].Fx, 0.4 * kP, 1e-8 * kP);  // sliding: mu_k
}

TEST(FrictionLaw, ForceAmplitudeAboveTheLowestMuIsRefused) {
  const std::string load = "path = sine\ncontrol = force\namplitude = 0.7\ncycles = 1";
  try {
    parse_scenario(sphere(32, 0.5, load, "law = static_kinetic\nmu_kinetic = 0.3\n"), "f",
                   fs::temp_directory_path());
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("load.amplitude"), std::string::npos) << e.what();
  }
}
