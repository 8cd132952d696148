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
// carries mu_k F_z, and an evolving mu (slip path, scale 1e-3 u*) reaches mu_final everywhere
// within the first step, whose rows then equal those of constant mu = mu_final (a uniform mu change
// reproduces the constant-mu solution with the new mu), reversals included.
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
  // The first step slides every node by ~2 u* = 2000 scales: it ends on mu_final already.
  for (std::size_t k = 1; k < c.size(); ++k) {
    EXPECT_NEAR(ev[k].Fx, c[k].Fx, 1e-8 * kP) << "row " << k;
    EXPECT_EQ(ev[k].stick_area, c[k].stick_area) << "row " << k;
  }
  EXPECT_NEAR(sk[2].Fx, 0.4 * kP, 1e-8 * kP);  // sliding: mu_k
}

// Evolving mu where every node slips alike: a flat on a periodic grid (uniform pressure p, no
// compliance to a uniform traction) slid by U from rest under displacement control slips by
// dU everywhere in every step. With X the slip path, X = U and F_x = mu(U) P exactly; with X
// the dissipated energy density, X' = mu(X) p along U, whose solution is
// e^{X/l} = y(U) = dmu/mu_f + (1 - dmu/mu_f) e^{p mu_f U / l}, mu = mu_f - dmu / y
// (dmu = mu_f - mu_0), and the dissipation is X times the area. The step's end takes mu(X_1)
// with the work's trapezoid (docs/algorithms.md, "Evolving friction"): second order in the
// step (F_x and the dissipation 4x closer per halving; with mu from the step's start, 2x),
// and the slip path's F_x exact at every row.
TEST(FrictionLaw, EvolvingSlidingConvergesAtSecondOrderInTheStep) {
  const double mu0 = 0.3, mu_f = 0.6, P = 1.0, L = 1e-3, p = P / (L * L), u_end = 4e-6;
  const double dmu = mu_f - mu0;
  auto slide = [&](const std::string& variable, double scale, int steps) {
    std::vector<double> ux;
    for (int k = 0; k <= steps; ++k) ux.push_back(u_end * k / steps);
    const fs::path table = shift_table(ux);
    const std::string text =
        "[material]\nE = 1e9\nnu = 0.3\nmu = " + format_number(mu0) +
        "\n[grid]\nn = 8\nlength = " + format_number(L) +
        "\nperiodic = true\n[surface]\ntype = flat\n[load]\nnormal_force = " + format_number(P) +
        "\npath = table\ncontrol = displacement\nallow_large_shift = true\ntable = " +
        table.string() + "\n[solver]\ntolerance = 1e-10\n[friction]\nlaw = evolving\nmu_final = " +
        format_number(mu_f) + "\nevolution = " + variable + "\nscale = " + format_number(scale) +
        "\n";
    auto rows = run(text);
    fs::remove(table);
    return rows;
  };
  // Slip path over U = 2 scales: F_x = mu(U) P at every row, to the solver's round-off.
  const double ell_s = 2e-6;
  const auto path_rows = slide("slip_path", ell_s, 8);
  for (std::size_t k = 1; k < path_rows.size(); ++k) {  // row 0: no tangential load yet
    const double ux = path_rows[k].Ux;
    EXPECT_NEAR(path_rows[k].Fx, (mu0 + dmu * (1 - std::exp(-ux / ell_s))) * P, 1e-12 * P) << ux;
  }
  // Dissipation over p mu_f U / l = 3: the ODE's closed form at U_end.
  const double ell_d = p * mu_f * u_end / 3.0;
  const double y = dmu / mu_f + (1 - dmu / mu_f) * std::exp(p * mu_f * u_end / ell_d);
  const double mu_end = mu_f - dmu / y, x_end = ell_d * std::log(y);
  std::vector<double> err_fx, err_d, err_path;
  for (int steps : {8, 16, 32}) {
    const StepRecord r = slide("dissipation", ell_d, steps).back();
    err_fx.push_back(std::abs(r.Fx / (mu_end * P) - 1));
    err_d.push_back(std::abs(r.dissipation / (x_end * L * L) - 1));
    // The slip path's dissipation P integral of mu(U) dU by the trapezoid: also second order.
    const double d_path = P * (mu_f * u_end - dmu * ell_s * (1 - std::exp(-u_end / ell_s)));
    err_path.push_back(std::abs(slide("slip_path", ell_s, steps).back().dissipation / d_path - 1));
    std::printf("[ %2d steps ] F_x %.3e, dissipation %.3e, slip-path dissipation %.3e\n", steps,
                err_fx.back(), err_d.back(), err_path.back());
  }
  // Second order: 4x per halving of the step; 3.5 = 2^1.8 leaves the next term of the error
  // expansion (relative size ~ the step, 1/16 of the range at 16 steps) its room.
  for (std::size_t i = 0; i + 1 < err_fx.size(); ++i) {
    EXPECT_GT(err_fx[i] / err_fx[i + 1], 3.5) << i;
    EXPECT_GT(err_d[i] / err_d[i + 1], 3.5) << i;
    EXPECT_GT(err_path[i] / err_path[i + 1], 3.5) << i;
  }
}

// Evolving mu under the normal-tangential coupling (steel ball on a rigid flat, beta = 0.286,
// +-0.6 mu_0 F_z, 16 steps per period): at the slip front nodes flip between slipping and
// stuck as the settling bound moves, and the bound alternates by 2 % at step 2 unless the step
// towards it is halved. The run settles every step and keeps the invariants: |F_x| within
// mu_final F_z, the dissipation never falling.
TEST(FrictionLaw, EvolvingCoupledCycleSettles) {
  const std::string text = fretbem_test::kSteelSphere32 +
                           "path = sine\ncontrol = force\namplitude = 0.6\ncycles = 1\n"
                           "steps_per_cycle = 16\n[solver]\ncoupling = coupled\nstiffness = false\n"
                           "[friction]\nlaw = evolving\nmu_final = 0.7\nscale = 5\n";
  const auto rows = run(text);
  ASSERT_EQ(rows.size(), 17u);
  for (std::size_t k = 1; k < rows.size(); ++k) {
    ASSERT_TRUE(std::isfinite(rows[k].Fx) && std::isfinite(rows[k].dissipation)) << k;
    EXPECT_LE(std::abs(rows[k].Fx), 0.7 * rows[k].Fz * (1 + 1e-9)) << k;
    EXPECT_GE(rows[k].dissipation, rows[k - 1].dissipation) << k;
  }
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
