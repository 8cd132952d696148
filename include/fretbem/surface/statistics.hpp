// Statistics of height fields: rms height and slope, radial PSD, fitted Hurst exponent.
#pragma once

#include <vector>

#include "fretbem/elastic/grid.hpp"

namespace fretbem {
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
  /// Width of the fit range in octaves, log2(q_hi / q_lo) = log2(n_min / 32) (<= 0: no fit).
  double hurst_fit_octaves = 0;
};

/// Below this fit width `fretbem surface` warns that the fitted Hurst exponent is unreliable.
/// Measured (fourier and midpoint, H = 0.3 and 0.8, seeds 1-5): at 1 octave (n = 64) fits
/// scatter from 0.66 to 1.55 for H = 0.8 and 0.12 to 1.04 for H = 0.3; from 2 octaves (n = 128)
/// on the largest error was 0.16 (midpoint) and 0.09 (fourier), at 4 octaves (n = 512) 0.07.
inline constexpr double kMinHurstFitOctaves = 2.0;
/// Statistics of a height field: rms about the mean; rms slope sqrt(<z_x^2 + z_y^2>) by
/// central differences (periodic wrap for periodic grids, one-sided first differences on the
/// edge rows/columns of free grids); Hurst exponent from a least-squares fit of log C vs
/// log q over 4 (2 pi / L) <= q <= q_Nyquist / 4 (see surface.cpp for why).
SurfaceStats surface_statistics(const Grid& grid, const Field& z);

}  // namespace fretbem
