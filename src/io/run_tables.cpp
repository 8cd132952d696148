#include "fretbem/io/run_tables.hpp"

#include <algorithm>

#include "fretbem/core/csv_reader.hpp"

namespace fretbem {

std::vector<StepRecord> read_timeseries(const std::filesystem::path& dir, std::size_t rows) {
  const auto table = csv::read_table(dir / "timeseries.csv", {.allow_nan = true, .max_rows = rows});
  std::vector<StepRecord> out;
  for (const auto& row : table.rows) out.push_back(StepRecord::from_values(row));
  return out;
}

std::optional<std::pair<int, double>> steady_energy(const std::filesystem::path& cycles) {
  const auto t = csv::read_table(cycles, {.allow_nan = true});
  const long steps = t.find("steps"), energy = t.find("dissipated_energy");
  if (steps < 0 || energy < 0 || t.rows.empty()) return std::nullopt;
  double most = 0;
  for (const auto& r : t.rows) most = std::max(most, r[steps]);
  for (auto r = t.rows.rbegin(); r != t.rows.rend(); ++r)
    if ((*r)[steps] == most) return std::pair{int(r->front()), (*r)[energy]};
  return std::nullopt;
}

}  // namespace fretbem
