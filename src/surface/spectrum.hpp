// What generation and statistics of surfaces share: FFTs of real fields, signed frequency
// indices, grid checks, rms height and slope (private to the surface layer).
#pragma once

#include <fftw3.h>

#include <complex>
#include <memory>
#include <numbers>
#include <vector>

#include "fretbem/elastic/grid.hpp"

namespace fretbem::surface_detail {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// Throws InputError (prefixed with what) unless the grid has >= 2 x 2 cells and h > 0.
void require_grid(const Grid& g, const char* what);
bool positive_finite(double v);

/// Half spectrum of a real (nx, ny) field: FFTW's row-major n0 = ny, n1 = nx layout matches
/// Field's column-major storage, so the complex array has nx/2 + 1 entries along x.
struct HalfSpectrum {
  int nx, ny, nxc;
  std::vector<std::complex<double>> c;
  HalfSpectrum(int nx_, int ny_) : nx(nx_), ny(ny_), nxc(nx_ / 2 + 1), c(std::size_t(nxc) * ny) {}
  std::complex<double>& operator()(int i, int j) { return c[std::size_t(j) * nxc + i]; }
  fftw_complex* data() { return reinterpret_cast<fftw_complex*>(c.data()); }
};

HalfSpectrum forward_fft(Field z);
Field inverse_fft(HalfSpectrum s);
/// Signed frequency index of FFT bin k out of n.
int signed_index(int k, int n);

/// rms slope sqrt(<z_x^2 + z_y^2>) by central differences (edges: periodic wrap, or
/// one-sided differences on free grids).
double rms_slope_of(const Grid& g, const Field& z);
double rms_about_mean(const Field& z);

}  // namespace fretbem::surface_detail
