// The CSV tables of a run read back: the rows a resumed run replays into its observers, and
// the energy per cycle its summary prints.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <utility>
#include <vector>

#include "fretbem/history/observables.hpp"

namespace fretbem {

/// The first `rows` rows of DIR/timeseries.csv as step records.
std::vector<StepRecord> read_timeseries(const std::filesystem::path& dir, std::size_t rows);

/// The cycle number and energy per cycle (J) of the last complete cycle of a plain run's
/// cycles.csv (every cycle but a shorter last one), or none when the path has no complete
/// cycle.
std::optional<std::pair<int, double>> steady_energy(const std::filesystem::path& cycles);

}  // namespace fretbem
