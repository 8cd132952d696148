// Rows of a wear run shared by the cycle-by-cycle and the ODE integrators: the cost guard's
// constants and how a simulated cycle is kept in the report. Internal to src/wear.
#pragma once

#include <cstdint>

#include "fretbem/wear/integrator.hpp"

namespace fretbem::wear_detail {

// Cost guard: an integrator step is worth its simulated cycles only when it covers at least
// kStepWorth times as many real cycles; otherwise the run simulates a stretch of cycles one by
// one (the cycle-mode arithmetic on the steady loop), at least kMinStretch long and doubling
// while the integrator stays unprofitable, so the integrator's wasted trials stay a
// geometrically bounded fraction of the cycles simulated.
inline constexpr double kStepWorth = 2.0;
inline constexpr double kMinStretch = 8.0;

/// Appends the cycle to the report without its rate field.
void keep(WearReport& rep, WearCycle c);
/// Logs the cycle, then keeps it.
void keep(WearReport& rep, WearCycle c, Observer& log);

/// The fingerprint of a worn depth W (m), this rank's slab of it: identifies the evaluations
/// made on an accepted state without keeping a copy of W per evaluation. Over all ranks
/// (collective): equal on every rank, so every rank takes the same accepted-row decisions.
std::uint64_t fingerprint(const Eigen::Ref<const Field>& W, const Communicator& comm);

/// Reference integrator: cycle after cycle, tractions carried, each cycle's wear applied
/// before the next.
WearReport integrate_cycles(Model& model, WearCycles& cyc, Observer& log,
                            const WearCheckpoint* resume, long max_steps);

/// The ODE dW/dN = w(z0 - W) by ARKODE (erk or dirk per `kind` and the stability cap).
WearReport integrate_ode(Model& model, WearCycles& cyc, Observer& log, WearIntegrator kind,
                         const WearCheckpoint* resume, long max_steps);

/// The absolute tolerance on W (m): wear.atol when given, else wear.rtol x the unworn
/// indentation; throws InputError for a wear.atol outside wear.rtol's range of that depth.
double absolute_tolerance(const Model& model, WearCycles& cyc);

}  // namespace fretbem::wear_detail
