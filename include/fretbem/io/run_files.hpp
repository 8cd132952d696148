// The files a run writes into its output folder, by name: what `run --overwrite` sets aside
// (replaced_results.hpp) and what `run --resume` reads or appends (resume_check.hpp).
#pragma once

namespace fretbem {

/// Every file a run writes into DIR (failed_solve.h5 aside: the report of a failed run, kept
/// where its error message says).
inline constexpr const char* kRunOutputFiles[] = {
    "timeseries.csv", "cycles.csv",        "result.h5",        "checkpoint.h5",    "result.xmf",
    "wear.xmf",       "checkpoint.h5.tmp", "result.h5.resume", "result.h5.damaged"};

}  // namespace fretbem
