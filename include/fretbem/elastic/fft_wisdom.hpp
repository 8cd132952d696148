// FFTW wisdom kept in a file, so that FFTW_MEASURE plans are measured once per transform size
// (and thread count) on a machine and later runs plan from the file at no cost.
// File: $FRETBEM_FFTW_WISDOM (a path; empty turns the file off), else
// $XDG_CACHE_HOME/fretbem/fftw-wisdom-<precision>, else ~/.cache/fretbem/fftw-wisdom-<precision>.
// A missing, unreadable or unwritable file is never an error: planning then measures in every
// process, as without wisdom. Measuring a size is serialised between processes by a lock file
// next to the wisdom (FILE.lock): one process measures while the others wait and then plan
// from its wisdom, so concurrent first runs (ensemble members, parallel tests) agree on one plan
// per size and give the same bits. A file that a run of another size extends later can change
// the plan of shared sub-problems (FFTW re-chooses them): a round-off change.
#pragma once

#include <filesystem>
#include <optional>

#include "fretbem/core/file_lock.hpp"
#include "fretbem/elastic/half_space.hpp"

namespace fretbem::fft_wisdom {

/// The wisdom file of one precision; empty when no location is known.
std::filesystem::path file(FftPrecision precision);
/// Whether wisdom can be kept: a file location is known and its folder exists (or can be made)
/// and is writable. solver.fft_plan = auto measures only then.
bool persistent(FftPrecision precision);
/// Holds the wisdom file's lock, waiting for another process that holds it; nullopt when there
/// is no file or it cannot be locked (planning then goes on unserialised).
std::optional<FileLock> lock(FftPrecision precision);
/// Imports the file again: what other processes measured since load().
void reload(FftPrecision precision);
/// Imports the file into FFTW's process-wide wisdom, once per process and precision. Call with
/// the planner serialised (FFTW's planner is not thread-safe).
void load(FftPrecision precision);
/// Merges the file with the process's wisdom and writes it back atomically (temporary file and
/// rename, so concurrent runs never see a half-written file). Planner serialised; errors ignored.
void save(FftPrecision precision);

}  // namespace fretbem::fft_wisdom
