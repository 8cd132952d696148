// Surface: height fields z(x, y) (m, peaks positive) of the rigid indenter — generation,
// import from files, and statistics.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "fretbem/grid.hpp"

namespace fretbem {

/// Self-affine random roughness (DESIGN §1 "Rough surfaces").
enum class RoughMethod { midpoint, fourier };

struct RoughSpec {
  double hurst = 0.8;                   ///< Hurst exponent H in (0, 1]
  std::optional<double> rms_height;     ///< target rms height (m); exactly one of the two
  std::optional<double> rms_slope;      ///< target rms slope (-)
  RoughMethod method = RoughMethod::midpoint;
  std::uint64_t seed = 1;               ///< explicit seed: same seed -> identical surface
  double rolloff_wavelength = 0.0;      ///< PSD flat for wavelengths above this (m); 0: none
  double cutoff_wavelength = 0.0;       ///< no roughness below this wavelength (m); 0: none
};

/// Parabolic sphere of radius R (m): z = -(x^2 + y^2) / (2 R), apex z = 0 at the centre.
Field sphere_surface(const Grid& grid, double radius);
/// Flat punch: z = 0 everywhere (a square flat punch covering the grid).
Field flat_surface(const Grid& grid);
/// Random rough surface, zero mean, scaled to the requested rms height or slope.
/// midpoint: random midpoint displacement on a 2^k periodic lattice, cropped to the grid.
/// fourier: Fourier filtering with PSD ~ q^(-2(1+H)) between roll-off and cut-off.
Field rough_surface(const Grid& grid, const RoughSpec& spec);

/// Loads a height map (m): HDF5 (.h5/.hdf5, 2-D dataset `dataset`, default the first 2-D
/// dataset found), NumPy (.npy, 2-D float64/float32, C or Fortran order) or whitespace-separated
/// text (anything else; one row per line). Rows run along y, columns along x:
/// z(i, j) = array[j][i]. Throws InputError naming the file on any problem.
Field load_height_map(const std::filesystem::path& file, const std::string& dataset = "");
/// Writes a height map in the same conventions (format from the extension: .h5, .npy, text).
void save_height_map(const std::filesystem::path& file, const Field& z);

struct SurfaceStats {
  double mean = 0, rms_height = 0, rms_slope = 0, min = 0, max = 0;
  double hurst_fit = 0;  ///< from the slope of the radially averaged PSD, -2(1+H)
};
/// Statistics of a height field: rms about the mean, rms slope by central differences
/// (periodic wrap for periodic grids), Hurst exponent fitted to the PSD.
SurfaceStats surface_statistics(const Grid& grid, const Field& z);

}  // namespace fretbem
