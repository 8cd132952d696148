// Recovery of a torn DIR/result.h5 on resume (issue 14): a kill or a full disk during an HDF5
// flush can leave the file unopenable while timeseries.csv (flushed row by row) and the
// checkpoint are intact. The time series and the run's description are rebuilt from them; the
// field snapshots of the damaged file cannot be, so it is kept beside as result.h5.damaged.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

#include "fretbem/history/model.hpp"

namespace fretbem {

/// DIR/result.h5 exists as a regular file that HDF5 cannot open.
bool result_file_torn(const std::filesystem::path& dir);

/// Renames DIR/result.h5 to result.h5.damaged and writes a new one as a fresh run would
/// (description, run id, scenario, initial surface) holding the first `rows` rows of
/// DIR/timeseries.csv. Throws InputError naming the file when timeseries.csv has fewer
/// well-formed rows or other columns. Returns the warning to print (one line).
std::string rebuild_result_file(const std::filesystem::path& dir, const Model& model,
                                std::size_t rows);

}  // namespace fretbem
