// What makes result.h5 and checkpoint.h5 self-describing (README "Fields"): the
// file attributes (program, format version, grid spacing and origin, periodic flag, array
// layout, output folder), the units of every field and time-series column, and the `x`/`y`
// coordinate datasets, registered as HDF5 dimension scales (H5DS) so that netCDF-4 readers
// (xarray, ncdump) see coordinates.
#pragma once

#include <hdf5.h>

#include <filesystem>
#include <string>
#include <vector>

#include "fretbem/core/hdf5.hpp"
#include "fretbem/elastic/grid.hpp"

namespace fretbem::io {

/// Format of result.h5: 1 = the unlabelled layout (float64 `state`); 2 = attributes, units,
/// dimension scales, uint8 `state`; 3 = saved steps stacked per field in /series (the step
/// groups' fields are views of them, with their own x and y scales; field_series.hpp);
/// 4 = integer `grid_shape`, the time series also as one variable per column in
/// /series/timeseries (column_series.hpp). Readers that only read datasets by their paths
/// work with all four.
constexpr int kResultFormatVersion = 4;

/// How a saved 2-D field is described: its units (SI, UDUNITS spelling) and a long name.
/// `flag` fields (state) are stored as uint8 with CF `flag_values` / `flag_meanings`.
struct FieldInfo {
  std::string units;
  std::string long_name;
  bool flag = false;
  /// A height map: a value in every cell, where shuffle + deflate saves ~12 % of the bytes at
  /// ~22 ms per 256^2 field (measured on rough_monotone's surface); stored uncompressed. The
  /// contact fields are zero off the contact and keep the filter.
  bool dense = false;
};

/// Elements per chunk of a stored field: 2 MiB of doubles.
inline constexpr hsize_t kFieldChunkElements = 1 << 18;

/// Whether a chunk of this many values is deflated: from 4096 on (32 KiB, a 64 x 64 grid).
/// Each deflated chunk costs zlib's set-up (~270 KiB allocated, 64 KiB of hash cleared);
/// on smaller chunks that outweighs the bytes saved: 1000 saved steps of two 8 x 8 fields took
/// 3.4 ms of CPU per step deflated, 1.2 ms not.
bool worth_compressing(hsize_t chunk_values);

/// The description of a field by its dataset name (last path component, e.g. "pressure",
/// "initial" under /surface, "final_worn_depth" under /wear); unknown names get units "".
FieldInfo field_info(const std::string& dataset_name);
/// Units of a /timeseries column (StepRecord::columns()); "1" for counts and flags.
std::string column_units(const std::string& column);

/// The legend of `state`: 0 open, 1 stick, 2 slip (NodeState).
inline constexpr const char* kStateMeanings = "open stick slip";

/// Writes (or replaces) the attributes on the file's root group: program, program_version,
/// format, format_version, grid_shape {ny, nx} (int64), grid_spacing {dy, dx} (m), grid_origin
/// {y0, x0} (m, centre of cell (0, 0)), grid_length {ly, lx} (m), periodic (0/1),
/// array_layout, cell_centred, output_dir. Pairs are in dataset axis order (y, x).
/// Throws std::runtime_error naming `what` (the file) on an HDF5 failure.
void write_file_attributes(hid_t file, const Grid& grid, const std::filesystem::path& output_dir,
                           const std::string& format, const std::string& what);

/// Creates the 1-D datasets /x and /y (cell centres, m) as dimension scales, unless present.
void write_grid_scales(hid_t file, const Grid& grid, const std::string& what);

/// Cell centres along an axis of n cells of side h (m): x_i = (i + 1/2 - n/2) h (Grid::x).
std::vector<double> cell_centres(int n, double h);

/// Creates the 1-D dataset `name` under `loc` holding these cell centres (m) as a dimension
/// scale named after its last path component ("x", "y"), unless it exists.
void write_coordinate(hid_t loc, const char* name, const std::vector<double>& centres,
                      const std::string& what);

/// Creates the empty 1-D dataset `name` under `loc`, extendible without limit along its one
/// axis (the saved steps, the time-series rows), chunked by 64 entries.
hdf5::Dataset create_extendible_vector(hid_t loc, const std::string& name, hid_t type,
                                       const std::string& what);

/// Writes a field's `units`, `long_name` and, for flag fields, `flag_values` and
/// `flag_meanings` (dataset_name: its last path component).
void write_field_attributes(hid_t dataset, const std::string& dataset_name,
                            const std::string& what);

/// Attaches /y and /x to dimensions 0 and 1 of a 2-D dataset whose shape is the grid's
/// (datasets of any other shape are left alone) and writes its `units` and `long_name`.
void describe_field(hid_t file, hid_t dataset, const std::string& dataset_name,
                    const std::string& what);

/// Writes (or replaces) a scalar string attribute.
void write_string_attribute(hid_t loc, const char* name, const std::string& value,
                            const std::string& what);

}  // namespace fretbem::io
