#include "fretbem/run/check.hpp"

#include <cstdio>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/format.hpp"
#include "fretbem/core/input_warning.hpp"
#include "fretbem/history/check_report.hpp"
#include "fretbem/history/cost_estimate.hpp"
#include "fretbem/history/edge_preflight.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/history/resolution.hpp"
#include "fretbem/io/resume_check.hpp"
#include "fretbem/wear/cost_estimate.hpp"

namespace fretbem {

namespace {

// The cost calibration runs a few solves: the report printed before stands while they run.
void print_cost(const Model& model) {
  const Scenario& sc = model.scenario;
  std::fflush(stdout);
  // A refusal the calibration meets is one the run meets too: it ends check with exit 2.
  try {
    if (sc.wear.law == WearLaw::none)
      std::fputs(describe(estimate_run_cost(sc), model.path.steps.size()).c_str(), stdout);
    else
      std::fputs(describe(estimate_wear_cost(sc), sc.wear).c_str(), stdout);
  } catch (const SolverError& e) {
    // The inputs are valid, so check's verdict stands; the failure the run will meet is said.
    std::printf("  cost: not estimated (the calibration solve failed)\n");
    std::fprintf(stderr, "fretbem: warning: the calibration solve failed: %s\n", e.what());
  }
}

}  // namespace

// The edge-contact refusal of the normal loading is solved only where Hertz says it may
// apply (edge_preflight.hpp).
int check_scenario(const Scenario& scenario, const std::string& name, const CheckOptions& options) {
  const auto model = prepare_model(scenario);
  const Scenario& sc = model->scenario;
  check_output_dir(sc.output.dir, options.overwrite);
  check_edge_contact_of_path(sc, model->path);
  release_input_warnings();  // every refusal run makes before its first step is behind
  if (sc.wear.law == WearLaw::none)
    std::printf("%s: ok (%d x %d grid, %zu load steps)\n", name.c_str(), sc.grid.nx, sc.grid.ny,
                model->path.steps.size());
  else
    std::printf("%s: ok (%d x %d grid, wear run of %s cycles)\n", name.c_str(), sc.grid.nx,
                sc.grid.ny, format_count(sc.wear.cycles).c_str());
  std::fputs(check_report(*model).c_str(), stdout);
  // Resolution and domain predicted from Hertz for spheres (resolution.hpp).
  if (const auto p = predict_sphere(sc, model->path))
    for (const auto& line : describe(*p, sc)) std::printf("  %s\n", line.c_str());
  if (options.estimate) print_cost(*model);
  return 0;
}

}  // namespace fretbem
