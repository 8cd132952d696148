// Wear integration over the cycle count N: which integrator runs a scenario (integrator.hpp),
// and how the worn depth is shared between the indenter and the half-space.
#include "fretbem/wear/integrator.hpp"

#include <cmath>

#include "fretbem/core/errors.hpp"
#include "wear_rows.hpp"

namespace fretbem {

Field indenter_worn(const Model& model, const Field& worn) {
  return model.scenario.wear.indenter_share * worn;
}

Field half_space_worn(const Model& model, const Field& worn) {
  return (1.0 - model.scenario.wear.indenter_share) * worn;
}

// Runs this short are simulated cycle by cycle whatever wear.integrator says: an ODE
// integrator cannot beat N + 1 simulated cycles there (its first steady cycle, one step per
// snapshot 1, 2, 5, 10, 20 of at least two evaluations each, and the final observation):
// measured at n = 32, Q = 0.6 mu P, k = 1e-11 (tools/bench/wear_sweep.py), arkode took 17.4
// simulated cycles for N = 10; see docs/wear.md for the crossover.
constexpr double kShortRun = 20.0;

WearReport integrate_wear(Model& model, WearCycles& cycles, WearLog* log,
                          const WearCheckpoint* resume, long max_steps) {
  if (!model.wear) throw InputError("wear.law: none (no wear to integrate)");
  const double N_end = model.scenario.wear.cycles;
  if (N_end <= kShortRun && N_end == std::floor(N_end))
    return wear_detail::integrate_cycles(model, cycles, log, resume, max_steps);
  switch (model.scenario.wear.integrator) {
    case WearIntegrator::cycle:
      return wear_detail::integrate_cycles(model, cycles, log, resume, max_steps);
    case WearIntegrator::arkode:
    case WearIntegrator::erk:
    case WearIntegrator::dirk:
      return wear_detail::integrate_ode(model, cycles, log, model.scenario.wear.integrator, resume,
                                        max_steps);
  }
  throw InputError("wear.integrator: unknown");
}

}  // namespace fretbem
