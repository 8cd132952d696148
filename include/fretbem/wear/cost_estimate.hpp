// What a wear run will cost, before it runs (`fretbem check`): the first steady
// cycle of the unworn surface is simulated at the scenario's grid; its largest slip gives the
// explicit stability cap. A second one, on the surface worn by the run's first step and started
// from the first one's solves as the run's evaluations are, gives the FFT convolutions and CPU
// time of one simulated cycle.
#pragma once

#include <string>

#include "fretbem/scenario/scenario.hpp"
#include "fretbem/wear/integrator.hpp"

namespace fretbem {

struct WearCostEstimate {
  double cap = 0.0;       ///< explicit stability cap 1 / (k_eq s_max K_max) (cycles per step)
  bool implicit = false;  ///< the integrator that runs is the implicit one (dirk)
  /// Expected simulated cycles, a range (expected_simulated_cycles). Measured accuracy:
  /// docs/reliability.md.
  double simulated_low = 0.0, simulated_high = 0.0;
  double convolutions_per_cycle = 0.0;  ///< FFT convolutions per simulated cycle
  double seconds_per_cycle = 0.0;       ///< CPU seconds per simulated cycle
  double calibration_seconds = 0.0;     ///< CPU time of the calibration, operators built (s)
};

/// The explicit runs measured 1.3-2.0x their lower estimate (error control shortens the first
/// steps, docs/reliability.md); the upper end of the range is this factor times the lower.
inline constexpr double kExplicitRangeFactor = 2.5;

/// Cost of a simulated cycle in a run over that of the calibration's warm evaluation: later
/// evaluations start farther from their answers (the worn surface has moved a whole step),
/// and the implicit method adds its inner products. Measured on rough_fretting_wear.ini and
/// fretting_wear.ini: convolutions 1.2-1.7 times (n = 64), CPU 1.1-1.7 times (n = 128-256,
/// docs/reliability.md).
inline constexpr double kWarmCostFactor = 1.2;
/// The runs' cost per simulated cycle lies within this factor either side of the estimate
/// (convolutions: ctest CostEstimate; CPU at n >= 128: docs/reliability.md).
inline constexpr double kWarmCostBand = 2.0;

/// Expected simulated cycles of a wear run, a range (cycles).
struct SimulatedCycles {
  double low = 0.0, high = 0.0;
  /// Geometric middle of the range: what a progress ETA counts on.
  double middle() const;
};

/// The range from the run's first steady cycle `c0` on the unworn surface (`cap` its explicit
/// stability cap, `per_evaluation` the simulated cycles of one steady cycle): cycle mode N + 1
/// exactly; erk from explicit_low to kExplicitRangeFactor times that; dirk from the empirical
/// model implicit_middle (cost_estimate.cpp) times kImplicitRange; all at most N + 1 (the cost
/// guard). `fretbem check` and the progress line of a wear run share it.
SimulatedCycles expected_simulated_cycles(const Scenario& sc, bool implicit, double cap,
                                          double per_evaluation, const WearCycle& c0);

/// Builds the model, simulates the steady cycle of the unworn surface; writes no file.
WearCostEstimate estimate_wear_cost(const Scenario& sc);

/// The report lines of `fretbem check`, each ending in '\n'.
std::string describe(const WearCostEstimate& e, const WearSpec& wear);

}  // namespace fretbem
