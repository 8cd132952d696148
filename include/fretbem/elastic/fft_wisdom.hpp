// FFTW wisdom kept in a file, so that FFTW_MEASURE plans are measured once per transform size
// (and thread count) on a machine and later runs plan from the file at no cost.
// File: $FRETBEM_FFTW_WISDOM (a path; empty turns the file off), else
// $XDG_CACHE_HOME/fretbem/fftw-wisdom-<precision>, else ~/.cache/fretbem/fftw-wisdom-<precision>.
// A missing, unreadable or unwritable file is never an error: planning then measures in every
// process, as without wisdom.
#pragma once

#include <filesystem>

#include "fretbem/elastic/half_space.hpp"

namespace fretbem::fft_wisdom {

/// The wisdom file of one precision; empty when no location is known.
std::filesystem::path file(FftPrecision precision);
/// Imports the file into FFTW's process-wide wisdom, once per process and precision. Call with
/// the planner serialised (FFTW's planner is not thread-safe).
void load(FftPrecision precision);
/// Merges the file with the process's wisdom and writes it back atomically (temporary file and
/// rename, so concurrent runs never see a half-written file). Planner serialised; errors ignored.
void save(FftPrecision precision);

}  // namespace fretbem::fft_wisdom
