// The shipped energy-per-cycle study's physics: a small sweep of the Hertz sphere of
// mindlin_cycle.ini below full sliding (force control) against Mindlin–Deresiewicz, and past
// it (displacement control) against the gross-slip line 4 mu P (D - 4u*/5); the per-member
// grid choice (study.max_grid_n) and its columns in sweep.csv.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "fretbem/core/csv_reader.hpp"
#include "fretbem/core/format.hpp"
#include "fretbem/elastic/closed_forms.hpp"
#include "fretbem/study/sweep_spec.hpp"
#include "sweep_test_util.hpp"

using namespace fretbem;
using namespace sweep_test;

namespace {

// mindlin_cycle.ini, by hand (Johnson, Contact Mechanics §§4.2, 7.2, 7.5): steel sphere
// R = 10 mm on a rigid-indenter half-space E = 210 GPa, nu = 0.3, mu = 0.5, P = 10 N,
// grid.length = 0.28 mm.
struct Sphere {
  double E = 210e9, nu = 0.3, mu = 0.5, P = 10, R = 0.01, L = 2.8e-4;
  double E_star() const { return E / (1 - nu * nu); }
  double G_star() const { return 4 * (E / (2 * (1 + nu))) / (2 - nu); }
  double a() const { return fretbem::closed_forms::hertz_contact_radius(P, R, E_star()); }
  double ustar() const {
    return fretbem::closed_forms::full_sliding_shift(
        mu, fretbem::closed_forms::hertz_approach(a(), R), E_star(), G_star());
  }
  // Johnson eq. 7.60: energy per cycle under +-Q*, q = Q*/mu P < 1.
  double md_energy(double q) const {
    return fretbem::closed_forms::mindlin_energy_per_cycle(q, mu, P, ustar());
  }
  // Displacement control +-D past full sliding (D >= u*): the rectangle 2D x 2 mu P less two
  // corners of (8/5) mu P u* each (the reversed branch needs 2u* to reach the opposite limit).
  double gross_slip_energy(double D) const { return 4 * mu * P * (D - 0.8 * ustar()); }
};

fs::path write_study(const fs::path& dir, const std::string& body) {
  const fs::path f = dir / "study.ini";
  std::ofstream(f) << "[study]\nscenario = " << FRETBEM_SOURCE_DIR
                   << "/scenarios/mindlin_cycle.ini\nout = " << (dir / "out").string() << "\n"
                   << body;
  return f;
}

// sweep.csv rows by member, column name to text.
std::vector<std::map<std::string, std::string>> sweep_rows(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  const auto head = csv::split_line(line);
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    const auto cells = csv::split_line(line);
    auto& r = rows.emplace_back();
    for (std::size_t i = 0; i < head.size() && i < cells.size(); ++i) r[head[i]] = cells[i];
  }
  return rows;
}

// n = 64 (a/h = 15.7), two cycles of 16 steps: each member runs in well under a second.
const std::string kSmall =
    "set = grid.n=64\nset = load.cycles=2\nset = load.steps_per_cycle=16\nset = "
    "output.fields=none\nset = solver.stiffness=false\nset = solver.tolerance=1e-10\n";

}  // namespace

// Below full sliding: Mindlin–Deresiewicz. The slip ring a (1 - (1 - q)^(1/3)) is w cells
// wide; where its edge falls between nodes it is misplaced by up to h/2 on each side, which
// (averaged round the circle) gives a relative energy error of order ((h/2)/w)^2 — 2.4 % at
// q = 0.5 (3.2 cells) and 0.6 % at q = 0.8 (6.5 cells) on this grid.
// Past full sliding: 4 mu P (D - 4u*/5) depends on the grid only through the compliance u*, which
// converges as the Hertz approach does, to O((h/a)^2): |dW| <= (16/5) mu P u* (h/a)^2.
TEST(EnergyPerCycleStudy, MindlinDeresiewiczBelowAndGrossSlipLinePastFullSliding) {
  const Sphere s;
  const double h = s.L / 64, us = s.ustar();
  {
    const fs::path d = scratch("epc_force");
    const auto r = shell(
        std::string(FRETBEM_BINARY) + " sweep " +
            write_study(d, kSmall + "[vary]\nload.amplitude = 0.5, 0.8\n").string() + " --quiet",
        d);
    ASSERT_EQ(r.status, 0) << r.err;
    const auto rows = sweep_rows(d / "out" / "sweep.csv");
    ASSERT_EQ(rows.size(), 2u);
    for (const auto& row : rows) {
      const double q = std::stod(row.at("load.amplitude"));
      const double w = s.a() * (1 - fretbem::closed_forms::cattaneo_stick_ratio(q)) / h;
      const double W = std::stod(row.at("dissipated_energy")), Wmd = s.md_energy(q);
      EXPECT_NEAR(W / Wmd, 1.0, std::pow(0.5 / w, 2)) << "q = " << q << ", ring " << w << " cells";
      EXPECT_NEAR(std::stod(row.at("ring_cells_predicted")), w, 0.01);
      EXPECT_EQ(row.at("resolution"), "resolved");
    }
  }
  const fs::path d = scratch("epc_gross");
  const std::string vary = "[vary]\nload.displacement_amplitude = " + format_number(2 * us) + ", " +
                           format_number(4 * us) + "\n";
  const auto r = shell(
      std::string(FRETBEM_BINARY) + " sweep " +
          write_study(d, kSmall + "set = load.control=displacement\n" + vary).string() + " --quiet",
      d);
  ASSERT_EQ(r.status, 0) << r.err;
  const auto rows = sweep_rows(d / "out" / "sweep.csv");
  ASSERT_EQ(rows.size(), 2u);
  for (const auto& row : rows) {
    const double D = std::stod(row.at("load.displacement_amplitude"));
    const double W = std::stod(row.at("dissipated_energy")), Wgs = s.gross_slip_energy(D);
    const double tol = 3.2 * s.mu * s.P * us * std::pow(h / s.a(), 2);
    EXPECT_NEAR(W, Wgs, tol) << "D/u* = " << D / us;
    EXPECT_EQ(row.at("resolution"), "gross slip");
    EXPECT_EQ(row.at("ring_cells_predicted"), "");
  }
}

// study.max_grid_n: a member whose slip ring spans under 2 cells runs on the smallest multiple
// of 8 that gives 2 cells (ceil(2 L / w)), capped; beyond the cap it is named under-resolved
// with the grid it needs. The others keep the base grid. (Spec only: nothing runs.)
TEST(EnergyPerCycleStudy, PerMemberGridRefinesUnderResolvedSlipRings) {
  const Sphere s;
  const fs::path d = scratch("grid_choice");
  const auto spec = load_sweep_spec(write_study(
      d, "set = grid.n=64\nmax_grid_n = 256\n[vary]\nload.amplitude = 0.02, 0.15, 0.5\n"));
  ASSERT_EQ(spec.grids.size(), 3u);
  auto needed = [&](double q) {
    const int n =
        int(std::ceil(2 * s.L / (s.a() * (1 - fretbem::closed_forms::cattaneo_stick_ratio(q)))));
    return (n + 7) / 8 * 8;
  };
  // q = 0.02: needs ~n = 1200 > 256: runs at 256 and says so.
  EXPECT_EQ(spec.grids[0].n, 256);
  EXPECT_LT(spec.grids[0].ring_cells, 2);
  EXPECT_EQ(spec.grids[0].resolution,
            "under-resolved: needs grid.n >= " + std::to_string(needed(0.02)));
  // q = 0.15: 1.67 cells at n = 64, refined to the needed grid.
  EXPECT_EQ(spec.grids[1].n, needed(0.15));
  EXPECT_GE(spec.grids[1].ring_cells, 2);
  EXPECT_EQ(spec.grids[1].resolution, "refined from 64");
  const auto sets = spec.member_sets(1);
  EXPECT_EQ(sets.back(), "grid.ny=" + std::to_string(needed(0.15)));
  // q = 0.5: 3.2 cells: kept.
  EXPECT_EQ(spec.grids[2].n, 64);
  EXPECT_EQ(spec.grids[2].resolution, "resolved");
  EXPECT_EQ(spec.member_sets(2).back(), "load.amplitude=0.5");
  // Without max_grid_n nothing is refined, but the under-resolved members are named.
  const auto plain =
      load_sweep_spec(write_study(d, "set = grid.n=64\n[vary]\nload.amplitude = 0.15\n"));
  EXPECT_EQ(plain.grids[0].n, 64);
  EXPECT_EQ(plain.grids[0].resolution,
            "under-resolved: needs grid.n >= " + std::to_string(needed(0.15)));
  // A rough surface has no prediction: empty columns.
  std::ofstream(d / "rough.ini") << "[study]\nscenario = " << FRETBEM_SOURCE_DIR
                                 << "/scenarios/rough_fretting_cycle.ini\nmax_grid_n = 256\n"
                                    "[vary]\nsurface.seed = 1, 2\n";
  const auto rough = load_sweep_spec(d / "rough.ini");
  EXPECT_EQ(rough.grids[0].resolution, "");
  EXPECT_EQ(rough.grids[0].n, rough.grids[0].base_n);
}
