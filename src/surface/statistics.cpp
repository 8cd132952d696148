// Surface statistics: rms height and slope, radial PSD, fitted Hurst exponent.
#include "fretbem/surface/statistics.hpp"

#include <cmath>
#include <limits>
#include <vector>

#include "fretbem/core/errors.hpp"
#include "spectrum.hpp"

namespace fretbem {

using namespace surface_detail;

namespace {

// ---------------------------------------------------------------------------------------
// Spectral statistics

// Separable Hann window, normalised to mean(w^2) = 1 so the windowed PSD keeps its level.
// Fields of free grids are not periodic: without a window their edge jump leaks a q^-2
// spectrum over everything steeper (Jacobs, Junge & Pastewka 2017, §3.3).
Field hann_window(int nx, int ny) {
  auto w1 = [](int n) {
    Eigen::ArrayXd w(n);
    for (int k = 0; k < n; ++k) w(k) = 0.5 * (1.0 - std::cos(kTwoPi * (k + 0.5) / n));
    return w;
  };
  const Field w = (w1(nx).matrix() * w1(ny).matrix().transpose()).array();
  return w / std::sqrt(w.square().mean());
}

RadialPsd radial_psd_impl(const Grid& grid, const Field& z) {
  Field f = z - z.mean();
  if (!grid.periodic) f *= hann_window(grid.nx, grid.ny);
  HalfSpectrum s = forward_fft(std::move(f));
  const double dqx = kTwoPi / grid.length_x(), dqy = kTwoPi / grid.length_y();
  const double dq = std::max(dqx, dqy), area = grid.length_x() * grid.length_y();
  const double norm = std::pow(grid.h, 4) / (kTwoPi * kTwoPi * area);  // see header
  const int rings = int(std::hypot(s.nx / 2 * dqx, s.ny / 2 * dqy) / dq) + 2;
  std::vector<double> wsum(rings), qsum(rings), csum(rings);
  for (int j = 0; j < s.ny; ++j)
    for (int i = 0; i < s.nxc; ++i) {
      const double q = std::hypot(i * dqx, signed_index(j, s.ny) * dqy);
      const int k = int(std::lround(q / dq));
      // Modes 0 < i < nx/2 stand for themselves and their conjugate (-i, -j).
      const double w = (i == 0 || 2 * i == s.nx) ? 1.0 : 2.0;
      wsum[k] += w;
      qsum[k] += w * q;
      csum[k] += w * norm * std::norm(s(i, j));
    }
  RadialPsd out;
  for (int k = 1; k < rings; ++k)
    if (wsum[k] > 0) {
      out.q.push_back(qsum[k] / wsum[k]);
      out.psd.push_back(csum[k] / wsum[k]);
    }
  return out;
}

// Least-squares slope of log C vs log q over 4 dq <= q <= q_Nyquist / 4. Below 4 dq a ring
// holds fewer than ~25 modes (scatter of tens of percent) and feels the window and the
// roll-off; above q_Nyquist / 4 the discrete lattice shows (the square Brillouin zone's
// corners, the finite-difference smoothing of midpoint displacement, aliasing). For n = 256
// this leaves q from 4 to 32 dq: almost a decade.
double fit_hurst(const Grid& grid, const RadialPsd& p) {
  const double dq = kTwoPi / std::min(grid.length_x(), grid.length_y());
  const double q_lo = 4.0 * dq, q_hi = std::numbers::pi / grid.h / 4.0;
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t k = 0; k < p.q.size(); ++k) {
    if (p.q[k] < q_lo || p.q[k] > q_hi || !(p.psd[k] > 0)) continue;
    const double x = std::log(p.q[k]), y = std::log(p.psd[k]);
    n += 1, sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  if (n < 3) return std::numeric_limits<double>::quiet_NaN();
  const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  return -0.5 * slope - 1.0;
}

}  // namespace

RadialPsd radial_psd(const Grid& grid, const Field& z) {
  require_grid(grid, "radial PSD");
  if (z.rows() != grid.nx || z.cols() != grid.ny)
    throw InputError("radial PSD: field shape does not match the grid");
  return radial_psd_impl(grid, z);
}

SurfaceStats surface_statistics(const Grid& grid, const Field& z) {
  require_grid(grid, "surface statistics");
  if (z.rows() != grid.nx || z.cols() != grid.ny)
    throw InputError("surface statistics: field shape does not match the grid");
  SurfaceStats s;
  s.mean = z.mean();
  s.rms_height = rms_about_mean(z);
  s.rms_slope = rms_slope_of(grid, z);
  s.min = z.minCoeff();
  s.max = z.maxCoeff();
  s.hurst_fit = fit_hurst(grid, radial_psd_impl(grid, z));
  // fit_hurst's range: q from 4 dq to q_Nyquist / 4 = (n_min / 8) dq.
  s.hurst_fit_octaves = std::log2(std::min(grid.nx, grid.ny) / 32.0);
  return s;
}

}  // namespace fretbem
