#include "kernel_values.hpp"

#include <cmath>
#include <cstdlib>
#include <numbers>

#include "fretbem/elastic/love.hpp"

namespace fretbem::kernel_values {

namespace {

double sinc(double x) {
  return x == 0.0 ? 1.0 : std::sin(x) / x;
}

}  // namespace

Constants::Constants(const Grid& grid, const Material& m, bool cerruti_kernels,
                     double cross_compliance)
    : h(grid.h),
      cz(1.0 / (std::numbers::pi * m.E_star())),
      ca(m.cerruti_a()),
      cb(m.cerruti_b()),
      es(m.E_star()),
      cross(cross_compliance),
      cerruti(cerruti_kernels),
      Lx(grid.length_x()),
      Ly(grid.length_y()) {}

Sample free_at(const Constants& c, int dx, int dy) {
  const double a = 0.5 * c.h, x = dx * c.h, y = dy * c.h;
  Sample s;
  const double i1 = love::I1(x, y, a, a);
  s.z = c.cz * i1;
  if (c.cerruti) {
    s.xx = c.ca * i1 + c.cb * love::Ixx(x, y, a, a);
    s.yy = c.ca * i1 + c.cb * love::Iyy(x, y, a, a);
    s.xy = c.cb * love::Ixy(x, y, a, a);
  }
  if (c.cross != 0.0) {
    s.zx = c.cross * love::Jx(x, y, a, a);
    s.zy = c.cross * love::Jy(x, y, a, a);
  }
  return s;
}

// K_d(q) = sum_k G(q_k) sinc(q_kx h/2) sinc(q_ky h/2), q_k = q + 2 pi k / h. The alternating
// tails are truncated at |k| <= 8 with half weight on the last term. The q = 0 mode is zero:
// displacements are measured from their mean.
Sample periodic_at(const Constants& c, int m0, int m1, int n0, int n1) {
  const double h = c.h, pi = std::numbers::pi;
  Sample s;
  if (m0 == 0 && m1 == 0) return s;
  const double qy0 = 2 * pi * (m0 <= n0 / 2 ? m0 : m0 - n0) / c.Ly;
  const double qx0 = 2 * pi * m1 / c.Lx;
  const bool cross = c.cross != 0.0;
  double sz = 0, sxx = 0, syy = 0, sxy = 0, szx = 0, szy = 0;
  constexpr int K = 8;
  for (int kx = -K; kx <= K; ++kx) {
    const double qx = qx0 + 2 * pi * kx / h, wx = std::abs(kx) == K ? 0.5 : 1.0;
    for (int ky = -K; ky <= K; ++ky) {
      const double qy = qy0 + 2 * pi * ky / h, wy = std::abs(ky) == K ? 0.5 : 1.0;
      const double q = std::hypot(qx, qy);
      if (q == 0.0) continue;
      const double w = wx * wy * sinc(0.5 * qx * h) * sinc(0.5 * qy * h);
      sz += w * 2.0 / (c.es * q);
      if (c.cerruti) {
        const double q3 = q * q * q;
        sxx += w * 2 * pi * (c.ca / q + c.cb * qy * qy / q3);
        syy += w * 2 * pi * (c.ca / q + c.cb * qx * qx / q3);
        sxy += w * (-2 * pi * c.cb * qx * qy / q3);
      }
      // Fourier transform of x/r^2 = grad(ln r)_x: i q_x (-2 pi / q^2); imaginary part.
      if (cross)
        szx += w * (-2 * pi * c.cross * qx / (q * q)),
            szy += w * (-2 * pi * c.cross * qy / (q * q));
    }
  }
  s.z = sz, s.xx = sxx, s.yy = syy, s.xy = sxy;
  // A real odd kernel has a real (here: zero) spectrum on the Nyquist modes of even sides.
  const bool nyquist = (n1 % 2 == 0 && m1 == n1 / 2) || (n0 % 2 == 0 && m0 == n0 / 2);
  if (cross && !nyquist) s.zx = szx, s.zy = szy;
  return s;
}

}  // namespace fretbem::kernel_values
