// Height-map files (m, peaks positive): HDF5, NumPy and text, read and written.
#pragma once

#include <filesystem>
#include <string>

#include "fretbem/elastic/grid.hpp"

namespace fretbem {
/// Loads a height map (m): HDF5 (.h5/.hdf5, 2-D dataset `dataset`, default the first 2-D
/// dataset found in name order), NumPy (.npy v1/v2/v3, 2-D '<f8' or '<f4', C or Fortran
/// order) or whitespace-separated text (anything else; one row per line, blank lines and
/// '#' comments skipped). Rows run along y, columns along x: z(i, j) = array[j][i].
/// Throws InputError naming the file on any problem (missing, unreadable, not 2-D, ragged
/// rows, non-numeric token (with its line), NaN/Inf values).
Field load_height_map(const std::filesystem::path& file, const std::string& dataset = "");
/// Writes a height map in the same conventions (format from the extension: .h5/.hdf5 as
/// dataset "height", .npy as '<f8' C order, otherwise text with round-trip exact decimals).
/// Throws InputError naming the file if it cannot be written or z holds NaN/Inf.
void save_height_map(const std::filesystem::path& file, const Field& z);

}  // namespace fretbem
