// The time series of result.h5 as one named variable per column, the layout netCDF-4 readers
// (xarray with h5netcdf, ncdump) label: /series/timeseries/COLUMN, 1-D float64 over the
// dimension scale `step` (int64, the step column), each with `units` (SI, UDUNITS spelling;
// column_units) and `coordinates = "time"`. Written as rows arrive, beside the 2-D
// /timeseries (rows x columns) that h5py readers use.
#pragma once

#include <hdf5.h>

#include <string>
#include <vector>

#include "fretbem/core/hdf5.hpp"

namespace fretbem::io {

class ColumnSeries {
 public:
  /// Where the variables live.
  static constexpr const char* group_name = "/series/timeseries";

  ColumnSeries() = default;
  /// Creates the group with one empty extendible dataset per column, replacing an old one.
  /// Columns without "step" have no axis to label: nothing is created, and append and
  /// truncate do nothing. Throws std::runtime_error naming `what` (the file).
  static ColumnSeries create(hid_t file, const std::vector<std::string>& columns,
                             const std::string& what);
  /// Opens the group when it holds these columns with `rows` entries each; otherwise creates
  /// it afresh from `table` (rows x columns, row-major: the 2-D /timeseries).
  static ColumnSeries open_or_rebuild(hid_t file, const std::vector<std::string>& columns,
                                      const std::vector<double>& table, const std::string& what);

  /// Appends one value to every column (row.size() == columns).
  void append(const std::vector<double>& row);
  /// Keeps the first `rows` entries.
  void truncate(std::size_t rows);
  bool valid() const { return !datasets_.empty(); }

 private:
  std::vector<hdf5::Dataset> datasets_;  // in column order
  std::size_t step_column_ = 0;
  hsize_t rows_ = 0;
  std::string what_;
};

}  // namespace fretbem::io
