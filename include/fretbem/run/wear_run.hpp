// A run with a wear law: the wear cycle simulation and integrator (wear/integrator.hpp) with
// the observers that write its outputs, then the summary on stdout.
#pragma once

#include "fretbem/wear/integrator.hpp"

namespace fretbem {

struct Checkpoint;

/// The `fretbem run` of a scenario with a wear law: timeseries.csv (rows of every simulated
/// cycle; time = simulated-cycle index + phase), cycles.csv (one row per simulated cycle),
/// result.h5 with wear snapshots, and DIR/checkpoint.h5 after every wear step. `resume`: a
/// checkpoint of this run to continue from; `max_steps` as integrate_wear. Prints the
/// simulated-cycle count unless quiet.
WearReport run_wear(Model& model, bool quiet, const Checkpoint* resume = nullptr,
                    long max_steps = -1);

}  // namespace fretbem
