// Surface generation: spheres, flat punches and self-affine random roughness (README, the
// `surface.*` keys).
#include "fretbem/surface/generate.hpp"

#include <cmath>
#include <random>
#include <string>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/format.hpp"
#include "spectrum.hpp"

namespace fretbem {

using namespace surface_detail;

namespace {

void validate_spec(const RoughSpec& s) {
  if (!(s.hurst > 0.0 && s.hurst <= 1.0))
    throw InputError("rough surface: Hurst exponent must be in (0, 1], got " +
                     std::to_string(s.hurst));
  if (s.rms_height.has_value() == s.rms_slope.has_value())
    throw InputError("rough surface: set exactly one of rms_height and rms_slope");
  const double target = s.rms_height ? *s.rms_height : *s.rms_slope;
  if (!positive_finite(target))
    throw InputError(std::string("rough surface: ") + (s.rms_height ? "rms_height" : "rms_slope") +
                     " must be positive and finite");
  if (!(s.rolloff_wavelength >= 0.0) || !(s.cutoff_wavelength >= 0.0) ||
      !std::isfinite(s.rolloff_wavelength) || !std::isfinite(s.cutoff_wavelength))
    throw InputError("rough surface: roll-off and cut-off wavelengths must be >= 0 and finite");
  if (s.method == RoughMethod::midpoint && (s.rolloff_wavelength > 0 || s.cutoff_wavelength > 0))
    throw InputError("rough surface: roll-off/cut-off wavelengths need method 'fourier'");
  if (s.rolloff_wavelength > 0 && s.cutoff_wavelength > 0 &&
      s.cutoff_wavelength >= s.rolloff_wavelength)
    throw InputError("rough surface: cut-off wavelength must be shorter than roll-off wavelength");
}

// ---------------------------------------------------------------------------------------
// Randomness. std::mt19937_64's sequence is fixed by the standard ([rand.predef]); the
// distributions are not, so uniform and normal deviates are made here: 53-bit uniforms and
// the Box-Muller transform (Box & Muller, Ann. Math. Stat. 29, 1958), cos branch first.

class Gaussian {
 public:
  explicit Gaussian(std::uint64_t seed) : engine_(seed) {}
  double operator()() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = (static_cast<double>(engine_() >> 11) + 1.0) * 0x1.0p-53;  // (0, 1]
    const double u2 = static_cast<double>(engine_() >> 11) * 0x1.0p-53;          // [0, 1)
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare_ = r * std::sin(kTwoPi * u2);
    has_spare_ = true;
    return r * std::cos(kTwoPi * u2);
  }

 private:
  std::mt19937_64 engine_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

// Names the keys that decide which wavelengths the grid holds: the grid (n, length) and the
// Fourier limits; no mode between them leaves nothing to scale.
std::string zero_roughness_message(const Grid& g, const RoughSpec& s) {
  std::string keys = "grid.nx x grid.ny = " + std::to_string(g.nx) + " x " + std::to_string(g.ny) +
                     ", grid.length = " + format_number(g.length_x()) + " m";
  if (s.cutoff_wavelength > 0)
    keys += ", surface.cutoff_wavelength = " + format_number(s.cutoff_wavelength) + " m";
  if (s.rolloff_wavelength > 0)
    keys += ", surface.rolloff_wavelength = " + format_number(s.rolloff_wavelength) + " m";
  return "surface.type = rough: the generated field has zero roughness (" + keys +
         "): no wavelength between the cell size and the cut-off is left to scale to " +
         (s.rms_height ? "surface.rms_height" : "surface.rms_slope") +
         "; raise grid.n, or set surface.cutoff_wavelength below grid.length";
}

// Removes the mean and scales to the requested rms height or slope. Both measures are
// homogeneous of degree one in z, so one multiplication makes them exact to round-off.
Field normalise(const Grid& g, Field z, const RoughSpec& s) {
  z -= z.mean();
  const double now = s.rms_height ? rms_about_mean(z) : rms_slope_of(g, z);
  if (!positive_finite(now)) throw InputError(zero_roughness_message(g, s));
  z *= (s.rms_height ? *s.rms_height : *s.rms_slope) / now;
  return z;
}

// ---------------------------------------------------------------------------------------
// Random midpoint displacement: the diamond-square algorithm of Fournier, Fussell & Carpenter
// (CACM 25, 1982) as written by Voss ("Random fractal forgeries", The Science of Fractal
// Images, 1988, MidPointFM2D without the "addition" option). Each half-step (diamond, then
// square) shrinks the lattice spacing by sqrt(2) and the displacement std by 2^(-H/2), so
// one full level shrinks the variance by 2^(-2H). On a periodic lattice all four corners
// are one point; it starts at 0 (the mean is removed afterwards anyway).
// Draw order: levels coarse to fine; per level the diamond points, then the square points,
// each row by row (j outer, i inner), one normal deviate per point.

void diamond_step(Field& a, int d, double delta, Gaussian& g) {
  const int m = int(a.rows()) - 1;  // N - 1, N a power of two: & m wraps periodically
  for (int j = d; j <= m; j += 2 * d)
    for (int i = d; i <= m; i += 2 * d)
      a(i, j) = 0.25 * (a((i - d) & m, (j - d) & m) + a((i + d) & m, (j - d) & m) +
                        a((i - d) & m, (j + d) & m) + a((i + d) & m, (j + d) & m)) +
                delta * g();
}

void square_step(Field& a, int d, double delta, Gaussian& g) {
  const int m = int(a.rows()) - 1;
  for (int j = 0; j <= m; j += d)
    for (int i = (j / d) % 2 == 0 ? d : 0; i <= m; i += 2 * d)
      a(i, j) =
          0.25 * (a((i - d) & m, j) + a((i + d) & m, j) + a(i, (j - d) & m) + a(i, (j + d) & m)) +
          delta * g();
}

Field midpoint_surface(const Grid& grid, double hurst, Gaussian& g) {
  int n = 1;
  while (n < std::max(grid.nx, grid.ny)) n *= 2;
  Field a = Field::Zero(n, n);
  const double shrink = std::pow(0.5, 0.5 * hurst);
  double delta = 1.0;
  for (int d = n / 2; d >= 1; d /= 2) {
    delta *= shrink;
    diamond_step(a, d, delta, g);
    delta *= shrink;
    square_step(a, d, delta, g);
  }
  return a.topLeftCorner(grid.nx, grid.ny);
}

// ---------------------------------------------------------------------------------------
// Fourier filtering (e.g. Persson et al., J. Phys.: Condens. Matter 17, R1, 2005; Jacobs,
// Junge & Pastewka, Surf. Topogr. 5, 013001, 2017): each mode gets a complex Gaussian
// amplitude of variance C(q) ~ q^(-2(1+H)), flat below the roll-off q_r and zero above the
// cut-off q_c. Draw order: the half spectrum row by row (j outer over all ny, i inner over
// 0..nx/2), two deviates (re, im) per mode, drawn for every mode whatever the filter, so a
// changed roll-off or cut-off filters the same random phases.

double filter_amplitude(double q, double hurst, double q_r, double q_c) {
  if (q == 0.0 || q > q_c) return 0.0;
  return std::pow(std::max(q, q_r) / q_r, -(1.0 + hurst));  // sqrt of C(q) / C(q_r)
}

// The x = 0 and x = Nyquist planes of a half spectrum hold both k_y and -k_y: make them
// Hermitian (and their self-conjugate points real, with the same variance) so that c2r
// returns the real field these amplitudes describe.
void make_hermitian(HalfSpectrum& s) {
  const int planes[2] = {0, s.nx % 2 == 0 ? s.nx / 2 : -1};
  for (int i : planes) {
    if (i < 0) continue;
    for (int j = 0; j < s.ny; ++j) {
      const int jc = (s.ny - j) % s.ny;
      if (jc == j)
        s(i, j) = std::sqrt(2.0) * s(i, j).real();
      else if (j > jc)
        s(i, j) = std::conj(s(i, jc));
    }
  }
}

Field fourier_surface(const Grid& grid, const RoughSpec& spec, Gaussian& g) {
  const double dqx = kTwoPi / grid.length_x(), dqy = kTwoPi / grid.length_y();
  const double q_r =
      spec.rolloff_wavelength > 0 ? kTwoPi / spec.rolloff_wavelength : std::min(dqx, dqy);
  const double q_c = spec.cutoff_wavelength > 0 ? kTwoPi / spec.cutoff_wavelength
                                                : std::numeric_limits<double>::infinity();
  HalfSpectrum s(grid.nx, grid.ny);
  for (int j = 0; j < s.ny; ++j)
    for (int i = 0; i < s.nxc; ++i) {
      const double re = g(), im = g();
      const double q = std::hypot(i * dqx, signed_index(j, s.ny) * dqy);
      s(i, j) =
          filter_amplitude(q, spec.hurst, q_r, q_c) * std::sqrt(0.5) * std::complex<double>(re, im);
    }
  make_hermitian(s);
  return inverse_fft(std::move(s));
}

}  // namespace

Field sphere_surface(const Grid& grid, double radius) {
  if (!positive_finite(radius))
    throw InputError("sphere surface: radius must be positive and finite");
  Field z(grid.nx, grid.ny);
  for (int j = 0; j < grid.ny; ++j)
    for (int i = 0; i < grid.nx; ++i)
      z(i, j) = -(grid.x(i) * grid.x(i) + grid.y(j) * grid.y(j)) / (2.0 * radius);
  return z;
}

Field flat_surface(const Grid& grid) {
  return grid.zeros();
}

Field rough_surface(const Grid& grid, const RoughSpec& spec) {
  require_grid(grid, "rough surface");
  validate_spec(spec);
  Gaussian g(spec.seed);
  Field z = spec.method == RoughMethod::midpoint ? midpoint_surface(grid, spec.hurst, g)
                                                 : fourier_surface(grid, spec, g);
  return normalise(grid, std::move(z), spec);
}

}  // namespace fretbem
