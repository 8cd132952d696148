#include "fretbem/io/result_recovery.hpp"

#include <hdf5.h>

#include "fretbem/core/csv_reader.hpp"
#include "fretbem/core/errors.hpp"
#include "fretbem/core/hdf5.hpp"
#include "fretbem/io/run_output.hpp"

namespace fretbem {

namespace fs = std::filesystem;

bool result_file_torn(const fs::path& dir) {
  const fs::path h5 = dir / io::Hdf5Writer::file_name;
  std::error_code ec;
  if (!fs::is_regular_file(h5, ec)) return false;  // missing: refused by the resume checks
  hdf5::silence();
  if (H5Fis_hdf5(h5.c_str()) <= 0) return true;
  const hdf5::File f(H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  return !f.valid();
}

std::string rebuild_result_file(const fs::path& dir, const Model& model, std::size_t rows) {
  const fs::path csv = dir / "timeseries.csv", h5 = dir / io::Hdf5Writer::file_name;
  const auto table = csv::read_table(csv, {.allow_nan = true, .max_rows = rows});
  const std::string why = " (result.h5 is damaged too: rerun with --overwrite)";
  if (table.columns != StepRecord::columns())
    throw InputError(csv.string() + ": not this fretbem's time-series columns" + why);
  if (table.rows.size() < rows)
    throw InputError(csv.string() + ": has " + std::to_string(table.rows.size()) +
                     " rows but the checkpoint is after " + std::to_string(rows) + why);
  fs::path kept = h5;
  kept += ".damaged";
  fs::rename(h5, kept);
  {
    ResultFile fresh(dir, model);
    for (const auto& row : table.rows) fresh.writer().append_row(row);
  }
  return "warning: " + h5.string() + " could not be opened (torn by a kill or a full disk); " +
         "rebuilt from timeseries.csv and checkpoint.h5 (" + std::to_string(rows) +
         " rows); its field snapshots are lost, the damaged file is kept as " + kept.string();
}

}  // namespace fretbem
