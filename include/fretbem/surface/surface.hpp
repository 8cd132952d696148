// Surface: height fields z(x, y) (m, peaks positive) of the rigid indenter — generation,
// import from files, and statistics.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "fretbem/elastic/grid.hpp"

namespace fretbem {

/// Self-affine random roughness (DESIGN §1 "Rough surfaces").
enum class RoughMethod { midpoint, fourier };

struct RoughSpec {
  double hurst = 0.8;                ///< Hurst exponent H in (0, 1]
  std::optional<double> rms_height;  ///< target rms height (m); exactly one of the two
  std::optional<double> rms_slope;   ///< target rms slope (-), as surface_statistics measures it
  RoughMethod method = RoughMethod::midpoint;
  std::uint64_t seed = 1;           ///< explicit seed: same seed -> identical surface
  double rolloff_wavelength = 0.0;  ///< fourier only: PSD flat for longer wavelengths (m); 0: none
  double cutoff_wavelength =
      0.0;  ///< fourier only: no roughness below this wavelength (m); 0: none
};

/// Parabolic sphere of radius R (m): z = -(x^2 + y^2) / (2 R), apex z = 0 at the centre.
/// Throws InputError unless R > 0.
Field sphere_surface(const Grid& grid, double radius);
/// Flat punch: z = 0 everywhere (a square flat punch covering the grid).
Field flat_surface(const Grid& grid);
/// Random rough surface, zero mean, scaled so that its rms height or rms slope (as
/// surface_statistics measures them on `grid`) equals the requested value.
/// midpoint: Fournier/Voss diamond-square random midpoint displacement on a periodic
///   2^k x 2^k lattice (2^k >= max(nx, ny)), cropped to the grid.
/// fourier: Fourier filtering with PSD ~ q^(-2(1+H)) between roll-off and cut-off; the
///   result is periodic on the grid.
/// Reproducibility: the only randomness is std::mt19937_64(spec.seed), whose output sequence
/// the C++ standard fixes, turned into normal deviates by our own Box-Muller transform (not
/// std::normal_distribution, which differs between standard libraries) in a documented
/// order. The same seed, grid and spec give a bitwise identical field with the same binary
/// on the same machine; across compilers/libm/FFTW builds, identical to round-off.
/// Throws InputError for an invalid spec (H outside (0, 1], not exactly one rms target, ...).
Field rough_surface(const Grid& grid, const RoughSpec& spec);

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

/// Radially averaged power spectral density C(q) (m^4) with the continuum normalisation
/// sum over all wavevectors of C(q) (2 pi)^2 / A = mean of z^2 (mean removed first), binned
/// in rings of width dq = 2 pi / min(Lx, Ly); q is the mean |q| of the modes in each ring.
/// Free-boundary grids are Hann-windowed first (their fields are not periodic), periodic
/// grids are not.
struct RadialPsd {
  std::vector<double> q;    ///< ring wavenumber (rad/m), increasing
  std::vector<double> psd;  ///< ring average of C(q) (m^4)
};
RadialPsd radial_psd(const Grid& grid, const Field& z);

struct SurfaceStats {
  double mean = 0, rms_height = 0, rms_slope = 0, min = 0, max = 0;
  double hurst_fit = 0;  ///< from the slope of the radially averaged PSD, -2(1+H); NaN if
                         ///< the grid is too small for the fit range
};
/// Statistics of a height field: rms about the mean; rms slope sqrt(<z_x^2 + z_y^2>) by
/// central differences (periodic wrap for periodic grids, one-sided first differences on the
/// edge rows/columns of free grids); Hurst exponent from a least-squares fit of log C vs
/// log q over 4 (2 pi / L) <= q <= q_Nyquist / 4 (see surface.cpp for why).
SurfaceStats surface_statistics(const Grid& grid, const Field& z);

}  // namespace fretbem
