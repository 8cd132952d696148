// Friction laws against closed forms: a static/kinetic Cattaneo ramp converges to Cattaneo's
// solution with mu_k; after gross sliding a law that has moved mu uniformly reproduces the
// constant-mu solution with the new mu; a sliding contact carries mu_k F_z.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "fretbem/core/errors.hpp"
#include "support/hertz.hpp"
#include "support/temp_dir.hpp"

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

fs::path shift_table(const std::vector<double>& ux) {
  const fs::path f = fretbem_test::process_temp_dir() / "shift.csv";
  std::ofstream out(f);
  out.precision(17);
  out << "time,Ux\n";
  for (std::size_t k = 0; k < ux.size(); ++k) out << k << "," << ux[k] << "\n";
  return f;
}

}  // namespace

// Static/kinetic Cattaneo ramp to Q = 0.9 mu_k P (mu_s = 0.5, mu_k = 0.35). The continuum
// limit is Cattaneo's with mu_k: the slip annulus carries mu_k p, and a stick zone r < c whose
// traction held more than mu_k p at r = c would need the flat-punch term A / sqrt(c^2 - r^2),
// unbounded at the front, past mu_s p; so A = 0 and c/a = (1 - Q/(mu_k P))^(1/3), the shift
// U = mu_k (E*/G*)(a^2 - c^2)/R (docs/algorithms.md, "Static/kinetic friction"). A front node held
// to mu_s adds a force ~ sqrt(h) (order 1/2: U 2.3 % low at n = 64). Checked: U against the
// closed form at n = 32 and 64 (a = 8, 16 cells), converging at order >= 1; the stick radius
// within a cell; one ramp step and eight give the same answer (no error of the step).
TEST(FrictionLaw, StaticKineticRampConvergesToCattaneoWithMuKinetic) {
  const double mu_k = 0.35, q = 0.9, a = 0.25;
  const double c = a * closed_forms::cattaneo_stick_ratio(q);
  const double u_closed =
      fretbem_test::unit_full_sliding_shift(mu_k) * closed_forms::cattaneo_shift_ratio(q);
  const std::string friction = "law = static_kinetic\nmu_kinetic = 0.35\n";
  auto ramp = [&](int n, int steps) {
    const std::string load =
        "path = ramp\ncontrol = force\namplitude = " + format_number(q * mu_k / 0.5) +
        "\nsteps = " + std::to_string(steps);
    return run(sphere(n, 0.5, load, friction)).back();
  };
  std::vector<double> err;
  for (int n : {32, 64}) {
    const StepRecord r = ramp(n, 8);
    err.push_back(std::abs(r.Ux / u_closed - 1));
    const double cells = std::sqrt(r.stick_area / M_PI) * n;
    EXPECT_NEAR(cells, c * n, 1.0) << "n = " << n;
    EXPECT_NEAR(r.Fx, q * mu_k * kP, 1e-9 * kP);
  }
  EXPECT_LT(err[1], 1e-3);
  EXPECT_GT(err[0] / err[1], 2.0) << err[0] << " " << err[1];  // order >= 1 in h
  const StepRecord one = ramp(32, 1), eight = ramp(32, 8);
  EXPECT_NEAR(one.Ux, eight.Ux, 1e-6 * u_closed);
  EXPECT_EQ(one.stick_area, eight.stick_area);
}

// Displacement control far past sliding: once every node slides, a static/kinetic contact
// carries mu_k F_z, and an evolving mu (slip path, scale 1e-3 u*) reaches mu_final everywhere,
// after which its rows equal those of constant mu = mu_final (a uniform mu change reproduces
// the constant-mu solution with the new mu), reversals included.
TEST(FrictionLaw, UniformChangeReproducesConstantMu) {
  const double u = fretbem_test::unit_full_sliding_shift(0.6);
  const fs::path table = shift_table({0, 3 * u, 6 * u, 4 * u, 2 * u, 0, 3 * u});
  // Gross sliding to 6 u*, past the contact radius: the friction laws, not the small-slip
  // geometry, are under test.
  const std::string load =
      "path = table\ncontrol = displacement\nallow_large_shift = true\ntable = " + table.string();
  std::ostringstream evolving;
  evolving << "law = evolving\nmu_final = 0.6\nevolution = slip_path\nscale = " << 1e-3 * u << "\n";
  const auto ev = run(sphere(48, 0.3, load, evolving.str()));
  const auto c = run(sphere(48, 0.6, load, "law = constant\n"));
  const auto sk = run(sphere(48, 0.6, load, "law = static_kinetic\nmu_kinetic = 0.4\n"));
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
