// HalfSpace's kernel spectra: the exact cell influence coefficients (love.hpp) of the free
// (zero-padded) and the periodic grid, transformed once per grid.
#include <vector>

#include "fretbem/elastic/half_space.hpp"
#include "half_space_fft.hpp"
#include "kernel_values.hpp"

namespace fretbem {

// Free boundary: kernel sampled at offsets -(n-1)..(n-1) wrapped onto the 2n-periodic padded
// grid; zero-padding the load makes the circular convolution equal the linear one.
void HalfSpace::build_free_kernels(const Material& m) {
  Fft& F = *fft_;
  const Engine<double>& E = F.builder();
  const bool cer = coupling_ != Coupling::analogy, cross = cross_ != 0.0;
  const kernel_values::Constants c(grid_, m, cer, cross_);
  const std::size_t nr = std::size_t(E.n0) * E.n1;
  kz_space_.resize(E.n1, E.n0);
  std::vector<double> kxx(cer ? nr : 0), kyy(cer ? nr : 0), kxy(cer ? nr : 0);
  std::vector<double> kzx(cross ? nr : 0), kzy(cross ? nr : 0);
  for (int m0 = 0; m0 < E.n0; ++m0) {
    const int dy = m0 <= grid_.ny ? m0 : m0 - E.n0;
    for (int m1 = 0; m1 < E.n1; ++m1) {
      const int dx = m1 <= grid_.nx ? m1 : m1 - E.n1;
      const kernel_values::Sample s = kernel_values::free_at(c, dx, dy);
      kz_space_(m1, m0) = s.z;
      const std::size_t k = std::size_t(m0) * E.n1 + m1;
      if (cer) kxx[k] = s.xx, kyy[k] = s.yy, kxy[k] = s.xy;
      if (cross) kzx[k] = s.zx, kzy[k] = s.zy;
    }
  }
  self_ = kz_space_(0, 0);
  F.sz = F.spectrum_of(kz_space_.data());
  if (cer) {
    F.sxx = F.spectrum_of(kxx.data());
    F.syy = F.spectrum_of(kyy.data());
    F.sxy = F.spectrum_of(kxy.data());
  }
  if (cross) {
    F.szx = F.spectrum_of(kzx.data(), 1);
    F.szy = F.spectrum_of(kzy.data(), 1);
  }
}

// Periodic surface: the discrete kernel spectrum of every mode (kernel_values::periodic_at).
void HalfSpace::build_periodic_kernels(const Material& m) {
  Fft& F = *fft_;
  Engine<double>& E = F.builder();
  const bool cer = coupling_ != Coupling::analogy, cross = cross_ != 0.0;
  const kernel_values::Constants c(grid_, m, cer, cross_);
  const std::size_t ns = std::size_t(E.n0) * E.nc;
  const double inv_n = 1.0 / (double(E.n0) * E.n1);
  F.sz.assign(ns, 0.0);
  if (cer) F.sxx.assign(ns, 0.0), F.syy.assign(ns, 0.0), F.sxy.assign(ns, 0.0);
  if (cross) F.szx.assign(ns, 0.0), F.szy.assign(ns, 0.0);
  for (int m0 = 0; m0 < E.n0; ++m0) {
    for (int m1 = 0; m1 < E.nc; ++m1) {
      const kernel_values::Sample s = kernel_values::periodic_at(c, m0, m1, E.n0, E.n1);
      const std::size_t k = std::size_t(m0) * E.nc + m1;
      F.sz[k] = s.z * inv_n;
      if (cer) F.sxx[k] = s.xx * inv_n, F.syy[k] = s.yy * inv_n, F.sxy[k] = s.xy * inv_n;
      if (cross) F.szx[k] = s.zx * inv_n, F.szy[k] = s.zy * inv_n;
    }
  }
  // Real-space kernel (for sparse updates): inverse transform of the spectrum.
  for (std::size_t k = 0; k < ns; ++k) E.c1[k][0] = F.sz[k], E.c1[k][1] = 0.0;
  E.c2r(E.c1.get());
  kz_space_.resize(E.n1, E.n0);
  std::copy_n(E.rout.get(), std::size_t(E.n0) * E.n1, kz_space_.data());
  self_ = kz_space_(0, 0);
}

}  // namespace fretbem
