// `fretbem check`: every refusal `fretbem run` makes before its first tangential solve, with
// run's line and exit code, then the report of what the run will do (README "Command line").
#pragma once

#include <string>

#include "fretbem/scenario/scenario.hpp"

namespace fretbem {

struct CheckOptions {
  bool overwrite = false;  ///< the run may replace another run's results in its folder
  bool estimate = true;    ///< calibrate and print the run's cost (a few solves)
};

/// Checks `sc` as `fretbem run` would — the model prepared (files read, memory guard,
/// pre-flight checks), the output folder, the edge contact of the normal loading — and prints
/// the report to stdout: the grid and steps, check_report, the resolution predicted for a
/// sphere and, with options.estimate, the cost. `name` is the scenario file as the user gave
/// it. Returns the exit code (0); throws InputError on a refusal.
int check_scenario(const Scenario& sc, const std::string& name, const CheckOptions& options);

}  // namespace fretbem
