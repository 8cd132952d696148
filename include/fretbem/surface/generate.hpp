// Generated surfaces: height fields z(x, y) (m, peaks positive) of the indenter — spheres,
// flat punches, self-affine random roughness.
#pragma once

#include <cstdint>
#include <optional>

#include "fretbem/elastic/grid.hpp"

namespace fretbem {

/// Self-affine random roughness (README, the `surface.*` keys; PSD ∝ q^{-2(1+H)}).
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

}  // namespace fretbem
