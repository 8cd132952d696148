// DIR/failed_solve.h5: the inputs of a failed solve (history/failed_solve.hpp), in the layout
// of result.h5 (fields {ny, nx} doubles). /inputs is text, one `key = value` per line
// (solve, control, target components, direction, units), /scenario the resolved scenario;
// fields: normal /surface, /pressure_start; tangential /bound, /tau0_c, /u0_c (c = 0, 1: the
// operator's components, x and y or the one direction).
#pragma once

#include <filesystem>

#include "fretbem/history/failed_solve.hpp"

namespace fretbem {

/// Writes DIR/failed_solve.h5 and returns its path. Throws InputError naming the file when it
/// cannot be written.
std::filesystem::path write_failed_solve(const std::filesystem::path& dir, const FailedSolve& f);

}  // namespace fretbem
