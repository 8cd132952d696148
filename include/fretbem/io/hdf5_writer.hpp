// Hdf5Writer: DIR/result.h5 with the resolved scenario, surfaces, per-step fields and the time
// series. HDF5 C API behind the interface; every write is followed by a flush, so an
// interrupted run leaves a readable file.
//
// Layout: fields are 2-D datasets of dims {ny, nx} (h5py's a[j, i] = f(i, j)), float64 except
// `state` (uint8: 0 open, 1 stick, 2 slip; format version 1 stored it as float64), each with
// `units` and `long_name`; saved steps are stacked per field name in a series group and
// `/fields/step_%06d/NAME` (attributes `step` (int64) and `time` (double) on the group) are
// views of them (field_series.hpp); `/timeseries` is an extendible [rows, ncols] double
// dataset with `columns` and `units` attributes (arrays of variable-length UTF-8 strings);
// text is a scalar variable-length UTF-8 string dataset.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "fretbem/elastic/grid.hpp"

namespace fretbem::io {

class Hdf5Writer {
 public:
  static constexpr const char* file_name = "result.h5";

  /// Creates DIR (and parents) if needed and DIR/result.h5, replacing any old file.
  /// Throws InputError naming the path if it cannot be created.
  /// `name` replaces result.h5 for other files of the same layout (failed_solve.h5).
  explicit Hdf5Writer(const std::filesystem::path& dir, const std::string& name = file_name);
  /// Opens an existing DIR/result.h5 for appending (resume): an existing /timeseries is
  /// continued with its columns. Throws InputError naming the path if it cannot be opened.
  static Hdf5Writer open_existing(const std::filesystem::path& dir);

  ~Hdf5Writer();
  Hdf5Writer(Hdf5Writer&&) noexcept;
  Hdf5Writer& operator=(Hdf5Writer&&) noexcept;

  /// Writes the file's self-description (root attributes: program, format version, grid
  /// spacing and origin, periodic flag, array layout, `output_dir`; see result_metadata.hpp)
  /// and the `/x`, `/y` dimension scales. Fields written afterwards whose shape is the grid's
  /// get the scales attached; every field gets `units` and `long_name`.
  void describe(const Grid& grid, const std::filesystem::path& output_dir);

  /// Scalar string dataset at `name` (e.g. "/scenario"); intermediate groups are created and
  /// an existing object of that name is replaced.
  void write_text(const std::string& name, const std::string& text);
  /// 2-D double dataset {ny, nx} at `path` (e.g. "/surface/initial"); replaces an old one.
  void write_field(const std::string& path, const Field& field);
  /// `path` as a second name of the existing object `existing` (an HDF5 hard link: readers see
  /// the same dataset, no bytes are written); replaces an old object of that name.
  void link(const std::string& existing, const std::string& path);
  /// Saves the fields of a step: appended to the family's series and viewed from the group
  /// /fields/step_%06d (attributes step and time; field_series.hpp). A step written before
  /// (e.g. by a resumed run) is replaced. `prefix` names the family (wear snapshots use
  /// "/wear/snapshot_").
  void write_step_fields(std::int64_t step, double time, const std::map<std::string, Field>& fields,
                         const std::string& prefix = "/fields/step_");

  /// Copies these groups of write_step_fields' layout (attributes step and time, one field
  /// per dataset) from the HDF5 file `source`: each is read whole (so a torn chunk is found
  /// now) and written as write_step_fields writes it. A group that cannot be read is left
  /// out and returned; a write that fails throws (resume of a file torn by a kill:
  /// result_recovery.hpp).
  std::vector<std::string> copy_step_groups(const std::filesystem::path& source,
                                            const std::vector<std::string>& groups);

  /// Creates /timeseries with these column names (replacing an old one). Needed once before
  /// append_row, unless open_existing found a time series.
  void start_timeseries(const std::vector<std::string>& columns);
  /// Appends one row (size must equal the column count, else std::invalid_argument).
  void append_row(const std::vector<double>& row);
  /// Keeps the first `rows` rows of the time series (resume from an earlier step).
  void truncate_timeseries(std::size_t rows);
  std::size_t timeseries_rows() const;
  const std::vector<std::string>& timeseries_columns() const;

  const std::filesystem::path& path() const;
  /// Closes the file now, checked (a close flushes: on a full disk that is where a write
  /// fails); throws std::runtime_error naming the path. The writer is unusable afterwards.
  void close();

 private:
  struct Impl;
  explicit Hdf5Writer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace fretbem::io
