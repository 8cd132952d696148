// HalfSpace's kernel spectra: the exact cell influence coefficients (love.hpp) of the free
// (zero-padded) and the periodic grid, transformed once per grid.
#include <cmath>
#include <numbers>
#include <vector>

#include "fretbem/elastic/half_space.hpp"
#include "fretbem/elastic/love.hpp"
#include "half_space_fft.hpp"

namespace fretbem {

namespace {

double sinc(double x) {
  return x == 0.0 ? 1.0 : std::sin(x) / x;
}

}  // namespace

// Free boundary: kernel sampled at offsets -(n-1)..(n-1) wrapped onto the 2n-periodic padded
// grid; zero-padding the load makes the circular convolution equal the linear one.
void HalfSpace::build_free_kernels(const Material& m) {
  Fft& F = *fft_;
  const Engine<double>& E = F.builder();
  const double h = grid_.h, a = 0.5 * h;
  const double cz = 1.0 / (std::numbers::pi * m.E_star());
  const bool cer = coupling_ != Coupling::analogy, cross = cross_ != 0.0;
  const double ca = m.cerruti_a(), cb = m.cerruti_b();
  const std::size_t nr = std::size_t(E.n0) * E.n1;
  kz_space_.resize(E.n1, E.n0);
  std::vector<double> kxx(cer ? nr : 0), kyy(cer ? nr : 0), kxy(cer ? nr : 0);
  std::vector<double> kzx(cross ? nr : 0), kzy(cross ? nr : 0);
  for (int m0 = 0; m0 < E.n0; ++m0) {
    const int dy = m0 <= grid_.ny ? m0 : m0 - E.n0;
    for (int m1 = 0; m1 < E.n1; ++m1) {
      const int dx = m1 <= grid_.nx ? m1 : m1 - E.n1;
      const double x = dx * h, y = dy * h;
      const double i1 = love::I1(x, y, a, a);
      kz_space_(m1, m0) = cz * i1;
      if (cer) {
        const std::size_t k = std::size_t(m0) * E.n1 + m1;
        kxx[k] = ca * i1 + cb * love::Ixx(x, y, a, a);
        kyy[k] = ca * i1 + cb * love::Iyy(x, y, a, a);
        kxy[k] = cb * love::Ixy(x, y, a, a);
      }
      if (cross) {
        const std::size_t k = std::size_t(m0) * E.n1 + m1;
        kzx[k] = cross_ * love::Jx(x, y, a, a);
        kzy[k] = cross_ * love::Jy(x, y, a, a);
      }
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

// Periodic surface: the discrete kernel spectrum is the alias sum of the continuous symbol
// times the cell's form factor, K_d(q) = sum_k G(q_k) sinc(q_kx h/2) sinc(q_ky h/2),
// q_k = q + 2 pi k / h. The alternating tails are truncated at |k| <= 8 with half weight on the
// last term. The q = 0 mode is zero: displacements are measured from their mean.
void HalfSpace::build_periodic_kernels(const Material& m) {
  Fft& F = *fft_;
  Engine<double>& E = F.builder();
  const double h = grid_.h, pi = std::numbers::pi;
  const double Lx = grid_.length_x(), Ly = grid_.length_y();
  const bool cer = coupling_ != Coupling::analogy, cross = cross_ != 0.0;
  const double ca = m.cerruti_a(), cb = m.cerruti_b(), es = m.E_star();
  const std::size_t ns = std::size_t(E.n0) * E.nc;
  const double inv_n = 1.0 / (double(E.n0) * E.n1);
  F.sz.assign(ns, 0.0);
  if (cer) F.sxx.assign(ns, 0.0), F.syy.assign(ns, 0.0), F.sxy.assign(ns, 0.0);
  if (cross) F.szx.assign(ns, 0.0), F.szy.assign(ns, 0.0);
  constexpr int K = 8;
  for (int m0 = 0; m0 < E.n0; ++m0) {
    const double qy0 = 2 * pi * (m0 <= E.n0 / 2 ? m0 : m0 - E.n0) / Ly;
    for (int m1 = 0; m1 < E.nc; ++m1) {
      const double qx0 = 2 * pi * m1 / Lx;
      if (m0 == 0 && m1 == 0) continue;
      double sz = 0, sxx = 0, syy = 0, sxy = 0, szx = 0, szy = 0;
      for (int kx = -K; kx <= K; ++kx) {
        const double qx = qx0 + 2 * pi * kx / h, wx = std::abs(kx) == K ? 0.5 : 1.0;
        for (int ky = -K; ky <= K; ++ky) {
          const double qy = qy0 + 2 * pi * ky / h, wy = std::abs(ky) == K ? 0.5 : 1.0;
          const double q = std::hypot(qx, qy);
          if (q == 0.0) continue;
          const double w = wx * wy * sinc(0.5 * qx * h) * sinc(0.5 * qy * h);
          sz += w * 2.0 / (es * q);
          if (cer) {
            const double q3 = q * q * q;
            sxx += w * 2 * pi * (ca / q + cb * qy * qy / q3);
            syy += w * 2 * pi * (ca / q + cb * qx * qx / q3);
            sxy += w * (-2 * pi * cb * qx * qy / q3);
          }
          // Fourier transform of x/r^2 = grad(ln r)_x: i q_x (-2 pi / q^2); imaginary part.
          if (cross)
            szx += w * (-2 * pi * cross_ * qx / (q * q)),
                szy += w * (-2 * pi * cross_ * qy / (q * q));
        }
      }
      const std::size_t k = std::size_t(m0) * E.nc + m1;
      F.sz[k] = sz * inv_n;
      if (cer) F.sxx[k] = sxx * inv_n, F.syy[k] = syy * inv_n, F.sxy[k] = sxy * inv_n;
      // A real odd kernel has a real (here: zero) spectrum on the Nyquist modes of even sides.
      const bool nyquist = (E.n1 % 2 == 0 && m1 == E.n1 / 2) || (E.n0 % 2 == 0 && m0 == E.n0 / 2);
      if (cross && !nyquist) F.szx[k] = szx * inv_n, F.szy[k] = szy * inv_n;
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
