#include "fretbem/io/result_recovery.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <vector>

#include "fretbem/core/csv_reader.hpp"
#include "fretbem/core/errors.hpp"
#include "fretbem/core/hdf5.hpp"
#include "fretbem/io/csv_writer.hpp"
#include "fretbem/io/run_output.hpp"

namespace fretbem {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void refuse(const fs::path& file, const std::string& what) {
  throw InputError(file.string() + ": " + what + "; refusing to resume");
}

bool same(double a, double b) {
  return a == b || (std::isnan(a) && std::isnan(b));
}

// A scalar variable-length string dataset (Hdf5Writer::write_text); nullopt if unreadable.
std::optional<std::string> read_text(hid_t file, const char* name) {
  if (H5Lexists(file, name, H5P_DEFAULT) <= 0) return std::nullopt;
  hdf5::Dataset d(H5Dopen2(file, name, H5P_DEFAULT));
  hdf5::Type type(d.valid() ? H5Dget_type(d.get()) : -1);
  if (!type.valid() || H5Tis_variable_str(type.get()) <= 0) return std::nullopt;
  char* p = nullptr;
  if (H5Dread(d.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &p) < 0) return std::nullopt;
  std::string s = p ? p : "";
  H5free_memory(p);
  return s;
}

// The first `rows` rows of /timeseries, row-major; nullopt if it is missing, of another
// shape, shorter (a stale flush) or unreadable.
std::optional<std::vector<double>> read_rows(hid_t file, std::size_t rows, std::size_t cols) {
  if (H5Lexists(file, "timeseries", H5P_DEFAULT) <= 0) return std::nullopt;
  hdf5::Dataset d(H5Dopen2(file, "timeseries", H5P_DEFAULT));
  hdf5::Space space(d.valid() ? H5Dget_space(d.get()) : -1);
  hsize_t dims[2] = {0, 0};
  if (!space.valid() || H5Sget_simple_extent_ndims(space.get()) != 2 ||
      H5Sget_simple_extent_dims(space.get(), dims, nullptr) < 0 || dims[1] != cols ||
      dims[0] < rows)
    return std::nullopt;
  std::vector<double> out(rows * cols);
  if (rows == 0) return out;
  const hsize_t start[2] = {0, 0}, count[2] = {rows, cols};
  H5Sselect_hyperslab(space.get(), H5S_SELECT_SET, start, nullptr, count, nullptr);
  hdf5::Space mem(H5Screate_simple(2, count, nullptr));
  if (H5Dread(d.get(), H5T_NATIVE_DOUBLE, mem.get(), space.get(), H5P_DEFAULT, out.data()) < 0)
    return std::nullopt;
  return out;
}

std::string numbered(const std::string& parent, const std::string& prefix, std::int64_t k) {
  char num[32];
  std::snprintf(num, sizeof num, "%06lld", static_cast<long long>(k));
  return parent + "/" + prefix + num;
}

// PARENT/PREFIX%06d groups numbered below `below`, as full paths. A PARENT whose link table
// a kill tore cannot be listed, but most of its groups still open by name (measured: 111 of
// 177): those are probed one by one, and the damage is added to `lost`.
std::vector<std::string> numbered_groups(hid_t file, const std::string& parent,
                                         const std::string& prefix, std::int64_t below,
                                         std::vector<std::string>& lost) {
  std::vector<std::string> out;
  if (H5Lexists(file, parent.c_str(), H5P_DEFAULT) <= 0) return out;
  const hdf5::Group g(H5Gopen2(file, parent.c_str(), H5P_DEFAULT));
  try {
    if (!g.valid()) throw std::runtime_error("cannot open");
    for (const auto& n : hdf5::link_names(g.get())) {
      if (n.rfind(prefix, 0) != 0) continue;
      const std::string digits = n.substr(prefix.size());
      if (digits.empty() || !std::all_of(digits.begin(), digits.end(), ::isdigit)) continue;
      if (std::stoll(digits) < below) out.push_back(parent + "/" + n);
    }
  } catch (const std::runtime_error&) {
    for (std::int64_t k = 0; k < below; ++k)
      if (const std::string name = numbered(parent, prefix, k);
          H5Lexists(file, name.c_str(), H5P_DEFAULT) > 0)
        out.push_back(name);
    hdf5::last_error();  // clears the stack
    lost.push_back("its " + parent + " group cannot be listed (" + std::to_string(out.size()) +
                   " groups found by name)");
  }
  return out;
}

// timeseries.csv as the first `rows` rows under today's columns, and how many columns the
// file has. A run written before load.tolerance existed has today's columns but the last,
// step_error, whose value in such a run is 0 (nothing was estimated): its rows get that 0.
// Earlier files lack columns whose values were never recorded, and are refused.
struct CheckedCsv {
  csv::Table table;
  std::size_t file_columns = 0;
};

// An earlier fretbem's timeseries.csv under today's header, replaced atomically, so that the
// resumed rows can be appended to it.
void rewrite_with_todays_columns(const fs::path& csv_path, const csv::Table& table) {
  const fs::path dir = csv_path.parent_path();
  const std::string staged = csv_path.stem().string() + ".resume";
  {
    io::CsvWriter out(dir, staged, table.columns);
    for (const auto& row : table.rows) out.row(row);
  }
  fs::rename(dir / (staged + ".csv"), csv_path);
}

CheckedCsv read_checked_csv(const fs::path& csv_path, std::size_t rows) {
  std::error_code ec;
  if (!fs::is_regular_file(csv_path, ec)) refuse(csv_path, "missing");
  CheckedCsv c{csv::read_table(csv_path, {.allow_nan = true, .max_rows = rows}), 0};
  const auto& today = StepRecord::columns();
  c.file_columns = c.table.columns.size();
  const bool before_step_control =
      today.back() == "step_error" && c.file_columns + 1 == today.size() &&
      std::equal(c.table.columns.begin(), c.table.columns.end(), today.begin());
  if (c.table.columns != today && !before_step_control)
    refuse(csv_path, "not this fretbem's time-series columns");
  if (c.table.rows.size() < rows)
    refuse(csv_path, "has " + std::to_string(c.table.rows.size()) +
                         " rows but the checkpoint is after " + std::to_string(rows));
  if (c.file_columns == today.size()) return c;
  for (auto& row : c.table.rows) row.push_back(0.0);
  c.table.columns = today;
  return c;
}

// The old file's run id and rows, where readable, must be the checkpoint's and the CSV's.
// Returns what of it is unreadable (then lost).
std::vector<std::string> check_old_file(hid_t old, const fs::path& h5, const fs::path& csv_path,
                                        const CheckedCsv& checked, const std::string& run_id,
                                        std::size_t rows) {
  std::vector<std::string> lost;
  const auto id = read_text(old, "run_id");
  if (id && *id != run_id)
    refuse(h5, "run id " + *id + " is not the checkpoint's " + run_id +
                   " (the outputs belong to another run)");
  if (!id) lost.push_back("its /run_id is unreadable");
  // An earlier fretbem's /timeseries has the columns its timeseries.csv had.
  const csv::Table& table = checked.table;
  const std::size_t cols = checked.file_columns;
  const auto ref = read_rows(old, rows, cols);
  if (!ref) {
    lost.push_back("its /timeseries is stale or unreadable");
    return lost;
  }
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t c = 0; c < cols; ++c)
      if (c >= table.rows[r].size() || !same(table.rows[r][c], (*ref)[r * cols + c]))
        refuse(csv_path, "row " + std::to_string(r + 1) + ", column " + table.columns[c] +
                             " differs from result.h5's /timeseries");
  return lost;
}

}  // namespace

std::string prepare_result_for_resume(const fs::path& dir, const Model& model,
                                      const std::string& run_id, const ResumeExtent& extent) {
  hdf5::silence();
  const fs::path h5 = dir / io::Hdf5Writer::file_name, csv_path = dir / "timeseries.csv";
  std::error_code ec;
  if (!fs::is_regular_file(h5, ec)) refuse(h5, "missing");
  const CheckedCsv checked = read_checked_csv(csv_path, extent.rows);
  const csv::Table& table = checked.table;

  std::vector<std::string> lost, groups;
  {
    hdf5::File old(H5Fis_hdf5(h5.c_str()) > 0 ? H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT)
                                              : -1);
    if (!old.valid()) {
      lost.push_back(
          "it cannot be opened (torn by a kill or a full disk), its field groups are "
          "lost");
    } else {
      lost = check_old_file(old.get(), h5, csv_path, checked, run_id, extent.rows);
      groups = numbered_groups(old.get(), "/fields", "step_", extent.field_steps, lost);
      const auto snaps = numbered_groups(old.get(), "/wear", "snapshot_", extent.snapshots, lost);
      groups.insert(groups.end(), snaps.begin(), snaps.end());
    }
  }
  const std::string fresh_name = std::string(io::Hdf5Writer::file_name) + ".resume";
  std::size_t copied = 0;
  try {
    io::Hdf5Writer fresh(dir, fresh_name);
    write_result_header(fresh, model);
    for (const auto& row : table.rows) fresh.append_row(row);
    const auto failed = fresh.copy_step_groups(h5, groups);
    copied = groups.size() - failed.size();
    if (!failed.empty())
      lost.push_back(std::to_string(failed.size()) + " of its " + std::to_string(groups.size()) +
                     " field groups are damaged (first " + failed.front() + ") and lost");
    fresh.close();
  } catch (...) {
    fs::remove(dir / fresh_name, ec);  // a full disk: the old file stays as it is
    throw;
  }
  fs::path kept = h5;
  kept += ".damaged";
  if (lost.empty())
    fs::remove(h5);
  else
    fs::rename(h5, kept);
  fs::rename(dir / fresh_name, h5);
  if (checked.file_columns < table.columns.size()) rewrite_with_todays_columns(csv_path, table);
  if (lost.empty()) return "";
  std::string why;
  for (const auto& l : lost) why += (why.empty() ? "" : "; ") + l;
  return "warning: " + h5.string() + ": " + why + "; rebuilt from timeseries.csv and " +
         "checkpoint.h5 (" + std::to_string(extent.rows) + " rows, " + std::to_string(copied) +
         " field groups copied whole), the damaged file kept as " + kept.string();
}

}  // namespace fretbem
