// Periodic contact against Westergaard's wavy-surface solution (Johnson, Contact Mechanics,
// §13.2): a rigid sinusoid z = Delta cos(2 pi x / lambda), uniform in y, on a periodic grid.
// Full contact needs the mean pressure p* = pi E* Delta / lambda; below it the contact strip
// has half-width a with  p_mean = p* sin^2(pi a / lambda).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "fretbem/contact/normal_solver.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/history/stepper.hpp"

using namespace fretbem;

namespace {

struct Wavy {
  int n;
  Grid grid;
  Material mat;
  double Delta = 1e-3, lambda = 1.0;
  Field z;
  explicit Wavy(int n_) : n(n_), grid(Grid::square(n_, 1.0, true)) {
    mat.body1 = {1.0, 0.0};
    z = grid.zeros();
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        z(i, j) = Delta * std::cos(2 * std::numbers::pi * grid.x(i) / lambda);
  }
  double p_star() const { return std::numbers::pi * mat.E_star() * Delta / lambda; }
};

}  // namespace

// Contact width at mean pressures 0.1 … 0.7 p*: each of the strip's two edges is located to
// within one cell (h = lambda / n), so the full width 2a is good to two cells.
TEST(Periodic, WestergaardContactWidth) {
  Wavy w(128);
  HalfSpace hs(w.grid, w.mat, Coupling::analogy);
  NormalSolver ns(hs, {1e-10, 5000});
  for (double f : {0.1, 0.3, 0.5, 0.7}) {
    const double pm = f * w.p_star();
    Field p;
    const auto r = ns.solve_force(w.z, pm * w.grid.length_x() * w.grid.length_y(), p);
    EXPECT_TRUE(r.converged);
    const double width = double((p.col(0) > 0).count()) * w.grid.h;  // 2a
    const double a = w.lambda / std::numbers::pi * std::asin(std::sqrt(f));
    EXPECT_NEAR(width, 2 * a, 2.0 * w.grid.h) << "p/p* = " << f;
    // Uniform in y: every column the same.
    EXPECT_LT((p.colwise() - p.col(0)).abs().maxCoeff(), 1e-8 * p.maxCoeff());
  }
}

// At and above p* the contact is complete and the pressure is
// p = p_mean + p* cos(2 pi x / lambda) (the full-contact Westergaard field).
TEST(Periodic, FullContactPressureField) {
  Wavy w(64);
  HalfSpace hs(w.grid, w.mat, Coupling::analogy);
  NormalSolver ns(hs, {1e-12, 5000});
  const double pm = 1.5 * w.p_star();
  Field p;
  ns.solve_force(w.z, pm * w.grid.length_x() * w.grid.length_y(), p);
  EXPECT_EQ((p > 0).count(), p.size());
  // The discrete kernel sees the cell average of the cosine: amplitude p* sinc(pi h/lambda).
  const double h = w.grid.h, s = std::sin(std::numbers::pi * h) / (std::numbers::pi * h);
  double worst = 0.0;
  for (int i = 0; i < w.n; ++i) {
    const double exact = pm + w.p_star() * std::cos(2 * std::numbers::pi * w.grid.x(i));
    worst = std::max(worst, std::abs(p(i, 0) - exact) / w.p_star());
  }
  std::printf("full contact: max |p - Westergaard| / p* = %.2e (cell-average effect %.1e)\n", worst,
              1 - s);
  EXPECT_LT(worst, 2 * (1 - s) + 1e-6);
}

// A flat in full contact on a periodic grid carries a uniform pressure, and a uniform traction
// moves no node (the periodic kernels have no mean mode): the stick set offers no compliance,
// so any shift slides the whole interface at once, F_x = mu F_z and the work mu F_z dU.
TEST(Periodic, FlatSlidesUnderDisplacementControl) {
  const std::filesystem::path table =
      std::filesystem::temp_directory_path() / "fretbem_periodic_slide.csv";
  std::ofstream(table) << "time,Ux\n0,0\n1,1e-6\n2,2.5e-6\n3,1e-6\n";
  const std::string text =
      "[material]\nE = 1e9\nnu = 0.3\nmu = 0.4\n[grid]\nn = 8\nlength = 1e-3\nperiodic = true\n"
      "[surface]\ntype = flat\n[load]\nnormal_force = 2\npath = table\ncontrol = displacement\n"
      "allow_large_shift = true\ntable = " +
      table.string() + "\n";
  auto model = build_model(parse_scenario(text, "t", std::filesystem::temp_directory_path()));
  Stepper st(*model);
  const double expected_fx[] = {0.0, 0.8, 0.8, -0.8}, work[] = {0.0, 0.8e-6, 2e-6, 3.2e-6};
  for (std::size_t k = 0; k < st.steps(); ++k) {
    const StepRecord r = st.advance(k);
    EXPECT_NEAR(r.Fx, expected_fx[k], 1e-12) << "row " << k;
    EXPECT_NEAR(r.dissipation, work[k], 1e-18) << "row " << k;
  }
  std::filesystem::remove(table);
}
