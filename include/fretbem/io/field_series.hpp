// Saved steps of result.h5: the fields of a family of saved steps (the run's /fields, the wear
// snapshots) kept as one extendible dataset per field name, and each step's group as views
// into it.
//
// Layout of a family (prefix "/fields/step_", series "/series/fields", index "step", time
// "time"):
//   SERIES/x, SERIES/y      cell centres (m), dimension scales
//   SERIES/INDEX            int64 [saved]: the step (the group number), dimension scale
//   SERIES/TIME             float64 [saved], over INDEX
//   SERIES/NAME             [saved][ny][nx], chunked one step per chunk, dimension scales
//                           INDEX, y, x attached once at creation, attribute coordinates = TIME
//   PREFIX%06d              group with attributes step and time; NAME in it is a virtual
//                           dataset of SERIES/NAME's slab of that step, with its own x and y
//                           scales
// A dimension scale records every dataset attached to it (REFERENCE_LIST, one attribute that
// grows with each attach and is rewritten whole), so scales shared by every saved step
// outgrew the object-header attribute limit (64 KiB) after ~4000 datasets and made each
// attach cost O(saved steps). Here every scale has a fixed number of datasets attached:
// a run may save any number of steps, and netCDF-4 readers (xarray with h5netcdf) see
// SERIES as NAME(INDEX, y, x) with coordinate values, and each step group as NAME(y, x).
#pragma once

#include <hdf5.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "fretbem/elastic/grid.hpp"

namespace fretbem::io {

/// Where a family of saved steps lives and what its axis is called.
struct StepFamily {
  std::string prefix;     ///< group of saved step K: PREFIX%06d
  std::string series;     ///< group of the stacked fields
  std::string index;      ///< dimension of the saved steps (the group numbers)
  std::string time;       ///< coordinate over it: the group's `time` attribute
  std::string time_name;  ///< its long_name
};

/// The family whose groups are named PREFIX%06d: "/fields/step_" (series "/series/fields",
/// index "step", time "time": load-path time) or "/wear/snapshot_" ("/series/wear",
/// "snapshot", "N": cycles). Throws std::invalid_argument for another prefix.
const StepFamily& step_family(const std::string& prefix);

/// Cell centres (m) of the grid the fields are on; empty when unknown (no scales written).
struct GridCoordinates {
  std::vector<double> x, y;
};

/// Saves the fields of step `index` at `time` in the family: appended to the series (an
/// index saved before keeps its place and is overwritten) and its group PREFIX%06d
/// (replaced). Throws std::runtime_error naming `what` (the file) on an HDF5 failure.
void write_saved_step(hid_t file, const StepFamily& family, std::int64_t index, double time,
                      const std::map<std::string, Field>& fields, const GridCoordinates& grid,
                      const std::string& what);

/// The 2-D field `name` of a step group, in double precision. A view (virtual dataset) is
/// read from its source slab directly, so that a source that cannot be read throws instead
/// of reading as fill values. Throws std::runtime_error.
Field read_saved_field(hid_t file, hid_t group, const std::string& name);

/// The names of the fields of a step group (its 2-D datasets; the x and y scales are not).
std::vector<std::string> saved_field_names(hid_t group);

}  // namespace fretbem::io
