// Hertz-sphere scenarios the tests share, and the helpers that run them: the unit sphere of
// the closed-form checks, a 32 x 32 steel ball, a step recorder and the energy of one
// load cycle. Header-only: each test executable includes it once.
#pragma once

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "fretbem/core/format.hpp"
#include "fretbem/elastic/closed_forms.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/history/stepper.hpp"

namespace fretbem_test {

using namespace fretbem;

/// Unit sphere: E = 1, nu = 0.3 against a rigid flat (E* = 1 / (1 - nu^2)), R = 1, unit
/// domain. This normal force gives the contact radius a = 1/4 (P = 4/3 E* a^3 / R).
inline double unit_hertz_force() {
  return closed_forms::hertz_force(0.25, 1.0, 1.0 / (1 - 0.09));
}

/// The unit sphere's scenario text on an n x n grid of side `length`, friction coefficient mu:
/// `load` is the body of the [load] section, `rest` follows verbatim (further sections).
inline std::string unit_sphere_ini(int n, const std::string& load, const std::string& rest,
                                   double mu = 0.5, double length = 1.0) {
  std::ostringstream s;
  s << "[material]\nE = 1\nnu = 0.3\nmu = " << format_number(mu) << "\n[grid]\nn = " << n
    << "\nlength = " << format_number(length) << "\n[surface]\ntype = sphere\nradius = 1\n[load]\n"
    << load << "\n"
    << rest;
  return s.str();
}

/// The unit sphere's full-sliding shift U* = mu delta E*/G* (m) for friction coefficient mu:
/// delta = a^2 / R = 1/16 at the force of unit_hertz_force().
inline double unit_full_sliding_shift(double mu) {
  Material m;
  m.body1 = {1.0, 0.3};
  return closed_forms::full_sliding_shift(mu, closed_forms::hertz_approach(0.25, 1.0), m.E_star(),
                                          m.G_star());
}

/// A steel ball: E = 210 GPa, nu = 0.3, mu = 0.5, R = 10 mm, F_z = 10 N on a 32 x 32
/// grid of side 0.28 mm; the text ends inside [load], callers append the path and sections.
inline const std::string kSteelSphere32 = R"([material]
E = 210e9
nu = 0.3
mu = 0.5
[grid]
n = 32
length = 2.8e-4
[surface]
type = sphere
radius = 0.01
[load]
normal_force = 10
)";

/// Every step's record of a run.
struct StepRecorder : Observer {
  std::vector<StepRecord> rows;
  void on_step(const StepRecord& r, const InterfaceState&, const Model&) override {
    rows.push_back(r);
  }
};

/// Runs a scenario text to its end with one observer of type R (a test's own recorder).
template <class R>
R run_recorded(const std::string& text) {
  auto model = build_model(parse_scenario(text, "test", std::filesystem::temp_directory_path()));
  Stepper stepper(*model);
  R rec;
  stepper.run({&rec});
  return rec;
}

inline std::vector<StepRecord> run_steps(const Scenario& sc) {
  auto model = build_model(sc);
  Stepper stepper(*model);
  StepRecorder rec;
  stepper.run({&rec});
  return rec.rows;
}

inline std::vector<StepRecord> run_steps(const std::string& text,
                                         const std::string& name = "test") {
  return run_steps(parse_scenario(text, name, std::filesystem::temp_directory_path()));
}

/// Trapezoid loop area sum (Fx + Fx') / 2 (Ux' - Ux) and nodal dissipation over time (c, c+1].
struct CycleEnergy {
  double loop = 0, nodal = 0;
};
inline CycleEnergy cycle_energy(const std::vector<StepRecord>& rows, int c) {
  CycleEnergy e;
  for (std::size_t k = 1; k < rows.size(); ++k) {
    if (!(rows[k].time > c + 1e-12 && rows[k].time <= c + 1 + 1e-12)) continue;
    e.loop += 0.5 * (rows[k].Fx + rows[k - 1].Fx) * (rows[k].Ux - rows[k - 1].Ux);
    e.nodal += rows[k].dissipation - rows[k - 1].dissipation;
  }
  return e;
}

}  // namespace fretbem_test
