// DIR/result.h5 of a resumed run, rebuilt from what is known to be whole.
//
// A kill during an HDF5 flush can leave result.h5 unopenable, openable with a stale
// /timeseries, or openable with metadata past the file's recorded end of allocation, which
// fails only at the next write (measured: "addr overflow" when a resumed run replaced a field
// group, 1 kill in 8 at n = 16 with fields every step). So a resume never writes into the old
// file. It writes a new one from timeseries.csv (flushed row by row, checked against the
// checkpoint and against the old file's rows where those are readable), copies the old file's
// field groups that belong to the checkpoint (each read back whole), and only then replaces
// the old file. Whatever of the old file could not be kept is named in a warning and the old
// file is kept beside as result.h5.damaged.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include "fretbem/history/model.hpp"

namespace fretbem {

/// What of the old result file belongs to a checkpoint.
struct ResumeExtent {
  std::size_t rows = 0;          ///< time-series rows the checkpoint is after
  std::int64_t field_steps = 0;  ///< keep /fields/step_K for K < field_steps
  std::int64_t snapshots = 0;    ///< keep /wear/snapshot_K for K < snapshots
};

/// Refuses (InputError naming the file, "refusing to resume") outputs that do not belong to
/// the checkpoint: a missing result.h5 or timeseries.csv, a timeseries.csv with other columns
/// or fewer than extent.rows well-formed rows, a result.h5 with another run id, or rows that
/// differ from result.h5's own. Otherwise replaces DIR/result.h5 by the rebuilt file and
/// returns "" when nothing was lost, else the one-line warning to print.
std::string prepare_result_for_resume(const std::filesystem::path& dir, const Model& model,
                                      const std::string& run_id, const ResumeExtent& extent);

}  // namespace fretbem
