// Height-map files (m, peaks positive): HDF5, NumPy (.npy, .npz), text and ISO 25178-72 x3p,
// read; HDF5, .npy and text written.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "fretbem/elastic/grid.hpp"

namespace fretbem {
/// Loads a height map (m): HDF5 (.h5/.hdf5, 2-D dataset `dataset`, default the only 2-D
/// dataset; several are refused, naming them), NumPy (.npy v1/v2/v3, 2-D '<f8' or '<f4', C or
/// Fortran order) or whitespace-separated text (anything else; one row per line, blank lines and
/// '#' comments skipped). Rows run along y, columns along x: z(i, j) = array[j][i].
/// Throws InputError naming the file on any problem (missing, unreadable, not 2-D, ragged
/// rows, non-numeric token (with its line), NaN/Inf values).
Field load_height_map(const std::filesystem::path& file, const std::string& dataset = "");

/// Axis order of a stored 2-D array: `yx` (fretbem's, rows along y: array[j][i] = z(x_i, y_j))
/// or `xy` (first index along x, as SurfaceTopography's .npy/.h5 readers take it).
enum class HeightLayout { yx, xy };

/// A height map read from a file, with the grid spacing (m) when the file carries one: x3p's
/// CX/CY increments, an .npz entry `spacing`, an HDF5 attribute `spacing` on the dataset
/// (one value, or two in the array's index order).
struct HeightMap {
  Field z;                   ///< z(i, j), i along x (m)
  std::optional<double> dx;  ///< spacing along x (m), from the file
  std::optional<double> dy;  ///< spacing along y (m), from the file
};

/// Like load_height_map, plus `.npz` (the entry named `dataset`, or the only one besides
/// `spacing`) and `.x3p`
/// (ISO 25178-72: axis order and spacing from the file; `layout` does not apply). For the
/// other formats `layout` says which array index runs along x.
HeightMap read_height_map(const std::filesystem::path& file, const std::string& dataset,
                          HeightLayout layout);
/// Writes a height map in the same conventions (format from the extension: .h5/.hdf5 as
/// dataset "height" with the attribute `spacing` (m) when given, .npy as '<f8' C order,
/// otherwise text with round-trip exact decimals; .npy and text carry no spacing).
/// Throws InputError naming the file if it cannot be written or z holds NaN/Inf.
void save_height_map(const std::filesystem::path& file, const Field& z,
                     std::optional<double> spacing = std::nullopt);

}  // namespace fretbem
