// Wear integration over the cycle count N: which integrator runs a scenario (integrator.hpp),
// and how the worn depth is shared between the indenter and the half-space.
#include "fretbem/wear/integrator.hpp"

#include "fretbem/core/errors.hpp"
#include "wear_rows.hpp"

namespace fretbem {

Field indenter_worn(const Model& model, const Field& worn) {
  return model.scenario.wear.indenter_share * worn;
}

Field half_space_worn(const Model& model, const Field& worn) {
  return (1.0 - model.scenario.wear.indenter_share) * worn;
}

WearReport integrate_wear(Model& model, WearCycles& cycles, Observer& log,
                          const WearCheckpoint* resume, long max_steps) {
  if (!model.wear) throw InputError("wear.law: none (no wear to integrate)");
  if (simulates_every_cycle(model.scenario.wear))
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
