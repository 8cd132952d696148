// Whether a run's output directory may be written (fresh run) or continued (resume): the
// checks that keep one run's results from being overwritten, mixed with another's, or
// continued from a checkpoint that does not fit (docs/reliability.md, "Resume checks").
// Every refusal is an InputError naming the file and the quantity.
#pragma once

#include <filesystem>
#include <string>

#include "fretbem/history/model.hpp"
#include "fretbem/io/checkpoint.hpp"

namespace fretbem {

/// A fresh run id: 16 hex digits from the clock and a random device.
std::string new_run_id();

/// Refuses (InputError naming `dir` and the files) when `dir` holds another run's results and
/// `overwrite` is not given; changes nothing (`fretbem check` asks it as `run` will). Returns
/// whether `dir` holds such results (to be replaced, `overwrite` given).
bool check_output_dir(const std::filesystem::path& dir, bool overwrite);

/// Before a fresh run into `dir`: refuses when `dir` holds another run's results
/// (timeseries.csv, cycles.csv, result.h5 or checkpoint.h5) unless `overwrite`; with it,
/// sets them aside until the new run has finished (replaced_results.hpp).
void prepare_output_dir(const std::filesystem::path& dir, bool overwrite);

/// Before a resume reads anything: refuses any run file of `dir` (run_files.hpp) that exists
/// but is not a regular file (a FIFO would block the resume, a folder fail it unnamed).
void check_output_files(const std::filesystem::path& dir);

/// Refuses (naming FILE:LINE) a blank or comment line among the header and the first `rows`
/// data rows of a CSV the resume keeps and appends to.
void check_finished_rows(const std::filesystem::path& csv, std::size_t rows);

/// Refuses a checkpoint whose stored quantities do not fit the model built from its own
/// scenario: field sizes, component count, finiteness, contact states, step counters, and the
/// fingerprints of its load path and initial surface (input_digest.hpp).
void validate_checkpoint(const Checkpoint& cp, const Model& model,
                         const std::filesystem::path& file);

}  // namespace fretbem
