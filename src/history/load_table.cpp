// Path tables: CSV with a `time` column and any of Fz, delta, Fx, Fy, Ux, Uy (SI units).
#include <algorithm>
#include <cmath>
#include <map>

#include "fretbem/core/csv_reader.hpp"
#include "fretbem/core/errors.hpp"
#include "fretbem/core/format.hpp"
#include "fretbem/history/load_path.hpp"
#include "fretbem/history/load_spline.hpp"

namespace fretbem {

namespace {

using Columns = std::map<std::string, std::vector<double>>;

// Table values are forces (N), lengths (m) and times in SI; the bounds are the scenario's
// (Reader::magnitude): a row Ux = 1e200 overflowed the solver's norms to a silent zero result.
void check_value(const std::filesystem::path& file, long line, const std::string& column,
                 double v) {
  const double a = std::abs(v);
  if (a == 0.0 || (a >= 1e-100 && a <= 1e100)) return;
  throw InputError(file.string() + ":" + std::to_string(line) + ": " + column + " = " +
                   format_number(v) +
                   " is outside [1e-100, 1e100] in magnitude, the range the solver's arithmetic "
                   "can carry (check the unit: SI)");
}

Columns read_columns(const std::filesystem::path& file, std::vector<long>& lines) {
  const csv::Table table = csv::read_table(file);
  lines = table.lines;
  static const std::vector<std::string> known{"time", "Fz", "delta", "Fx", "Fy", "Ux", "Uy"};
  Columns cols;
  for (const auto& n : table.columns) {
    if (std::find(known.begin(), known.end(), n) == known.end())
      throw InputError(file.string() + ": unknown column '" + n +
                       "' (expected time, Fz, delta, Fx, Fy, Ux, Uy)");
    if (cols.count(n)) throw InputError(file.string() + ": column '" + n + "' appears twice");
    cols[n];
  }
  for (std::size_t k = 0; k < table.rows.size(); ++k)
    for (std::size_t c = 0; c < table.rows[k].size(); ++c) {
      check_value(file, table.lines[k], table.columns[c], table.rows[k][c]);
      cols[table.columns[c]].push_back(table.rows[k][c]);
    }
  return cols;
}

void check_columns(const std::filesystem::path& file, const Columns& cols,
                   const std::vector<long>& lines) {
  const std::string f = file.string();
  if (!cols.count("time")) throw InputError(f + ": path table needs a 'time' column");
  const auto& t = cols.at("time");
  if (t.empty()) throw InputError(f + ": path table has no rows");
  for (std::size_t k = 1; k < t.size(); ++k)
    if (!(t[k] > t[k - 1]))
      throw InputError(f + ":" + std::to_string(lines[k]) + ": time must increase");
  if (cols.count("Fz") && cols.count("delta")) throw InputError(f + ": give Fz or delta, not both");
  const bool force = cols.count("Fx") || cols.count("Fy");
  const bool disp = cols.count("Ux") || cols.count("Uy");
  if (force && disp) throw InputError(f + ": give forces (Fx, Fy) or shifts (Ux, Uy), not both");
}

// load.interpolation = cubic: each row's slopes of the spline through the rows, column by
// column (normal load, target x, target y). The rows are the path's last steps; a step before
// them (the normal loading ahead of a first row with a tangential load) stays off the spline.
void set_spline_rates(const std::filesystem::path& file, const std::vector<double>& t,
                      const std::vector<long>& lines, LoadPath& path) {
  const std::size_t first = path.steps.size() - t.size();
  std::vector<double> normal, x, y;
  for (std::size_t k = first; k < path.steps.size(); ++k) {
    normal.push_back(path.steps[k].normal.value);
    x.push_back(path.steps[k].target.x());
    y.push_back(path.steps[k].target.y());
  }
  const auto dn = not_a_knot_slopes(t, normal), dx = not_a_knot_slopes(t, x),
             dy = not_a_knot_slopes(t, y);
  for (std::size_t k = 0; k < t.size(); ++k)
    path.steps[first + k].rate = PathRate{dn[k], Vec2(dx[k], dy[k])};
  // The rows' normal loads are positive; the spline between them must stay so (sub-steps
  // solve it), or the table asks for a load it does not hold.
  for (std::size_t k = 0; k + 1 < t.size(); ++k)
    if (!(hermite_minimum(normal[k], dn[k], normal[k + 1], dn[k + 1], t[k + 1] - t[k]) > 0.0))
      throw InputError(file.string() + ":" + std::to_string(lines[k]) + "-" +
                       std::to_string(lines[k + 1]) +
                       ": load.interpolation = cubic: the spline through the normal load falls "
                       "to zero or below between these rows; add rows there or use linear");
}

}  // namespace

LoadPath read_load_table(const std::filesystem::path& file, const LoadSpec& spec, double) {
  std::vector<long> lines;
  const Columns cols = read_columns(file, lines);
  check_columns(file, cols, lines);
  const auto& t = cols.at("time");
  auto col = [&](const char* n, std::size_t k) { return cols.count(n) ? cols.at(n)[k] : 0.0; };
  const bool disp = cols.count("Ux") || cols.count("Uy");
  const Control control = disp ? Control::displacement : Control::force;
  LoadPath path;
  for (std::size_t k = 0; k < t.size(); ++k) {
    NormalLoad normal;
    if (cols.count("Fz"))
      normal = {true, cols.at("Fz")[k]};
    else if (cols.count("delta"))
      normal = {false, cols.at("delta")[k]};
    else if (spec.indentation)
      normal = {false, *spec.indentation};
    else if (spec.normal_force)
      normal = {true, *spec.normal_force};
    else
      throw InputError(file.string() +
                       ": no normal load: add an Fz or delta column, or set "
                       "load.normal_force or load.indentation");
    if (!(normal.value > 0.0))
      throw InputError(file.string() + ":" + std::to_string(lines[k]) +
                       ": the normal load must be positive");
    const Vec2 target = disp ? Vec2(col("Ux", k), col("Uy", k)) : Vec2(col("Fx", k), col("Fy", k));
    // `cycle` is the integer part of time, as for a sine (0 on every row).
    if (k == 0)
      path.steps.push_back(
          {t[0], cycle_of_time(t[0]), normal, control, Vec2::Zero(), false, false, {}});
    if (k == 0 && target.norm() == 0.0) continue;
    path.steps.push_back({t[k], cycle_of_time(t[k]), normal, control, target, false, false, {}});
  }
  // Turning points: where the tangential motion reverses or the path ends.
  for (std::size_t k = 1; k + 1 < path.steps.size(); ++k) {
    const Vec2 a = path.steps[k].target - path.steps[k - 1].target;
    const Vec2 b = path.steps[k + 1].target - path.steps[k].target;
    path.steps[k].turning = a.dot(b) < 0.0;
  }
  if (path.steps.size() > 1) path.steps.back().turning = true;
  if (spec.interpolation == LoadInterpolation::cubic) set_spline_rates(file, t, lines, path);
  return path;
}

}  // namespace fretbem
