// Surface generation, height-map import/export and statistics (DESIGN §1 "Rough surfaces").
#include "fretbem/surface/surface.hpp"

#include <fftw3.h>
#include <hdf5.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <complex>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <mutex>
#include <numbers>
#include <random>
#include <sstream>
#include <string_view>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/format.hpp"
#include "fretbem/core/hdf5.hpp"

namespace fretbem {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// ---------------------------------------------------------------------------------------
// Validation

void require_grid(const Grid& g, const char* what) {
  if (g.nx < 2 || g.ny < 2 || !(g.h > 0.0) || !std::isfinite(g.h))
    throw InputError(std::string(what) +
                     ": grid needs at least 2 x 2 cells and a positive "
                     "finite spacing");
}

bool positive_finite(double v) {
  return v > 0.0 && std::isfinite(v);
}

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

// ---------------------------------------------------------------------------------------
// FFTW. The planner is process-wide and not thread-safe; FFTW >= 3.3.5 can serialise it
// itself (FFTW manual §5.4 "Thread safety"), which also protects plans made by other modules.

void make_planner_thread_safe() {
  static std::once_flag flag;
  std::call_once(flag, [] { fftw_make_planner_thread_safe(); });
}

struct PlanDeleter {
  void operator()(fftw_plan_s* p) const { fftw_destroy_plan(p); }
};
using Plan = std::unique_ptr<fftw_plan_s, PlanDeleter>;

// Half spectrum of a real (nx, ny) field: FFTW's row-major n0 = ny, n1 = nx layout matches
// Field's column-major storage, so the complex array has nx/2 + 1 entries along x.
struct HalfSpectrum {
  int nx, ny, nxc;
  std::vector<std::complex<double>> c;
  HalfSpectrum(int nx_, int ny_) : nx(nx_), ny(ny_), nxc(nx_ / 2 + 1), c(std::size_t(nxc) * ny) {}
  std::complex<double>& operator()(int i, int j) { return c[std::size_t(j) * nxc + i]; }
  fftw_complex* data() { return reinterpret_cast<fftw_complex*>(c.data()); }
};

HalfSpectrum forward_fft(Field z) {
  make_planner_thread_safe();
  HalfSpectrum s(int(z.rows()), int(z.cols()));
  Plan p(fftw_plan_dft_r2c_2d(s.ny, s.nx, z.data(), s.data(), FFTW_ESTIMATE));
  fftw_execute(p.get());
  return s;
}

Field inverse_fft(HalfSpectrum s) {
  make_planner_thread_safe();
  Field z(s.nx, s.ny);
  Plan p(fftw_plan_dft_c2r_2d(s.ny, s.nx, s.data(), z.data(), FFTW_ESTIMATE));
  fftw_execute(p.get());  // destroys s, which is a copy
  return z;
}

// Signed frequency index of FFT bin k out of n.
int signed_index(int k, int n) {
  return k <= n / 2 ? k : k - n;
}

// ---------------------------------------------------------------------------------------
// Slopes: central differences inside; at the edges periodic wrap, or one-sided first
// differences for free grids (the field has no values beyond its edge).

double diff_at(const Field& z, int i, int j, bool along_x, bool periodic, double h) {
  const int n = int(along_x ? z.rows() : z.cols());
  const int k = along_x ? i : j;
  auto v = [&](int m) { return along_x ? z(m, j) : z(i, m); };
  if (k > 0 && k < n - 1) return (v(k + 1) - v(k - 1)) / (2 * h);
  if (periodic) return (v((k + 1) % n) - v((k - 1 + n) % n)) / (2 * h);
  return k == 0 ? (v(1) - v(0)) / h : (v(n - 1) - v(n - 2)) / h;
}

double rms_slope_of(const Grid& g, const Field& z) {
  double sum = 0.0;
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const double sx = diff_at(z, i, j, true, g.periodic, g.h);
      const double sy = diff_at(z, i, j, false, g.periodic, g.h);
      sum += sx * sx + sy * sy;
    }
  return std::sqrt(sum / double(g.size()));
}

double rms_about_mean(const Field& z) {
  return std::sqrt((z - z.mean()).square().mean());
}

// Removes the mean and scales to the requested rms height or slope. Both measures are
// homogeneous of degree one in z, so one multiplication makes them exact to round-off.
Field normalise(const Grid& g, Field z, const RoughSpec& s) {
  z -= z.mean();
  const double now = s.rms_height ? rms_about_mean(z) : rms_slope_of(g, z);
  if (!positive_finite(now))
    throw InputError(
        "rough surface: generated field has zero roughness on this grid "
        "(grid too small, or cut-off wavelength too long)");
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

// ---------------------------------------------------------------------------------------
// Height-map files: shared helpers

[[noreturn]] void file_error(const std::filesystem::path& file, const std::string& what) {
  throw InputError("height map '" + file.string() + "': " + what);
}

// Grids index with int; 2^30 nodes (8 GiB of doubles) is far beyond any BEM grid. Checked
// before allocating, since a corrupt header can declare any shape.
void require_sane_shape(const std::filesystem::path& file, unsigned long long ny,
                        unsigned long long nx) {
  constexpr unsigned long long kMaxSide = 1ull << 24, kMaxNodes = 1ull << 30;
  if (nx == 0 || ny == 0) file_error(file, "array is empty");
  if (nx > kMaxSide || ny > kMaxSide || nx * ny > kMaxNodes)
    file_error(file,
               "array shape (" + std::to_string(ny) + ", " + std::to_string(nx) + ") is too large");
}

void require_finite(const std::filesystem::path& file, const Field& z) {
  for (int j = 0; j < z.cols(); ++j)
    for (int i = 0; i < z.rows(); ++i)
      if (!std::isfinite(z(i, j)))
        file_error(
            file, "NaN or Inf value at row " + std::to_string(j) + ", column " + std::to_string(i));
}

std::string lower_extension(const std::filesystem::path& file) {
  std::string e = file.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

std::string read_all(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) file_error(file, "cannot open for reading");
  std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) file_error(file, "read error");
  return data;
}

// ---------------------------------------------------------------------------------------
// HDF5 (C API). Errors are reported through return codes; HDF5's automatic printing of its
// error stack is silenced for the duration of each call into this module.

int dataset_rank(hid_t dset) {
  hdf5::Space space(H5Dget_space(dset));
  return space.valid() ? H5Sget_simple_extent_ndims(space.get()) : -1;
}

// H5Lvisit callback: stops (returns 1) at the first hard link to a 2-D dataset.
herr_t find_2d_dataset(hid_t group, const char* name, const H5L_info_t* info, void* found) {
  if (info->type != H5L_TYPE_HARD) return 0;
  hdf5::Dataset d(H5Dopen2(group, name, H5P_DEFAULT));
  if (!d.valid() || dataset_rank(d.get()) != 2) return 0;
  *static_cast<std::string*>(found) = name;
  return 1;
}

std::string choose_dataset(const std::filesystem::path& file, hid_t f, const std::string& name) {
  if (!name.empty()) return name;
  std::string found;
  if (H5Lvisit(f, H5_INDEX_NAME, H5_ITER_INC, find_2d_dataset, &found) < 0 || found.empty())
    file_error(file, "no 2-D dataset in the file");
  return found;
}

Field read_h5_dataset(const std::filesystem::path& file, hid_t d, const std::string& name) {
  const std::string where = "dataset '" + name + "' ";
  hdf5::Space space(H5Dget_space(d));
  if (!space.valid() || H5Sget_simple_extent_ndims(space.get()) != 2)
    file_error(file, where + "is not 2-D");
  hsize_t dims[2];
  H5Sget_simple_extent_dims(space.get(), dims, nullptr);
  hdf5::Type type(H5Dget_type(d));
  const H5T_class_t cls = H5Tget_class(type.get());
  if (cls != H5T_FLOAT && cls != H5T_INTEGER) file_error(file, where + "is not numeric");
  require_sane_shape(file, dims[0], dims[1]);
  Field z(static_cast<Eigen::Index>(dims[1]), static_cast<Eigen::Index>(dims[0]));  // {ny, nx}
  if (H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, z.data()) < 0)
    file_error(file, where + "could not be read");
  return z;
}

Field load_h5(const std::filesystem::path& file, const std::string& dataset) {
  hdf5::Quiet quiet;
  if (H5Fis_hdf5(file.c_str()) <= 0) file_error(file, "not an HDF5 file");
  hdf5::File f(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  if (!f.valid()) file_error(file, "cannot open HDF5 file");
  const std::string name = choose_dataset(file, f.get(), dataset);
  hdf5::Dataset d(H5Dopen2(f.get(), name.c_str(), H5P_DEFAULT));
  if (!d.valid()) file_error(file, "no dataset '" + name + "'");
  return read_h5_dataset(file, d.get(), name);
}

void save_h5(const std::filesystem::path& file, const Field& z) {
  hdf5::Quiet quiet;
  hdf5::File f(H5Fcreate(file.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT));
  if (!f.valid()) file_error(file, "cannot create HDF5 file");
  const hsize_t dims[2] = {hsize_t(z.cols()), hsize_t(z.rows())};  // {ny, nx}
  hdf5::Space space(H5Screate_simple(2, dims, nullptr));
  hdf5::Dataset d(H5Dcreate2(f.get(), "height", H5T_IEEE_F64LE, space.get(), H5P_DEFAULT,
                             H5P_DEFAULT, H5P_DEFAULT));
  if (!space.valid() || !d.valid() ||
      H5Dwrite(d.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, z.data()) < 0)
    file_error(file, "cannot write dataset 'height'");
}

// ---------------------------------------------------------------------------------------
// NumPy .npy (format spec: numpy.lib.format / NEP 1): magic "\x93NUMPY", version bytes,
// little-endian header length (uint16 for 1.0, uint32 for 2.0/3.0), then a Python dict
// literal with 'descr', 'fortran_order', 'shape', padded with spaces to a multiple of 64.

constexpr std::string_view kNpyMagic("\x93NUMPY", 6);

// Byte-wise little-endian access: independent of the host's byte order.
template <class U>
U load_le(const char* p) {
  U v = 0;
  for (std::size_t b = 0; b < sizeof(U); ++b) v |= U(static_cast<unsigned char>(p[b])) << (8 * b);
  return v;
}

template <class U>
void append_le(std::string& out, U v) {
  for (std::size_t b = 0; b < sizeof(U); ++b) out += char((v >> (8 * b)) & 0xff);
}

struct NpyHeader {
  std::string descr;
  bool fortran = false;
  std::vector<long long> shape;
  std::size_t data_offset = 0;
};

// Text after "'key':" in the header dict, or throws.
std::string_view dict_value(const std::filesystem::path& file, std::string_view h,
                            const std::string& key) {
  const auto k = h.find("'" + key + "'");
  const auto colon = k == h.npos ? h.npos : h.find(':', k);
  if (colon == h.npos) file_error(file, "npy header has no '" + key + "'");
  auto v = h.substr(colon + 1);
  return v.substr(std::min(v.find_first_not_of(' '), v.size()));
}

std::vector<long long> parse_shape(const std::filesystem::path& file, std::string_view v) {
  const auto close = v.find(')');
  if (v.empty() || v[0] != '(' || close == v.npos) file_error(file, "npy shape is malformed");
  std::vector<long long> shape;
  std::string_view rest = v.substr(1, close - 1);
  while (!rest.empty()) {
    const auto comma = std::min(rest.find(','), rest.size());
    std::string_view tok = rest.substr(0, comma);
    tok.remove_prefix(std::min(tok.find_first_not_of(' '), tok.size()));
    if (!tok.empty()) {
      long long n = -1;
      const auto r = std::from_chars(tok.data(), tok.data() + tok.size(), n);
      if (r.ec != std::errc() || n < 0) file_error(file, "npy shape is malformed");
      shape.push_back(n);
    }
    rest.remove_prefix(std::min(comma + 1, rest.size()));
  }
  return shape;
}

NpyHeader parse_npy_header(const std::filesystem::path& file, const std::string& data) {
  if (data.size() < 10 || std::string_view(data).substr(0, 6) != kNpyMagic)
    file_error(file, "not a NumPy .npy file");
  const int major = static_cast<unsigned char>(data[6]);
  if (major < 1 || major > 3) file_error(file, "unsupported .npy version " + std::to_string(major));
  const std::size_t lenbytes = major == 1 ? 2 : 4;
  if (data.size() < 8 + lenbytes) file_error(file, "truncated .npy header");
  const std::size_t hlen =
      major == 1 ? load_le<std::uint16_t>(&data[8]) : load_le<std::uint32_t>(&data[8]);
  NpyHeader h;
  h.data_offset = 8 + lenbytes + hlen;
  if (data.size() < h.data_offset) file_error(file, "truncated .npy header");
  const std::string_view dict(data.data() + 8 + lenbytes, hlen);
  const auto d = dict_value(file, dict, "descr");
  const auto end = d.size() > 1 ? d.find(d[0], 1) : d.npos;
  if (end == d.npos || (d[0] != '\'' && d[0] != '"')) file_error(file, "npy descr is malformed");
  h.descr = std::string(d.substr(1, end - 1));
  h.fortran = dict_value(file, dict, "fortran_order").starts_with("True");
  h.shape = parse_shape(file, dict_value(file, dict, "shape"));
  return h;
}

double npy_value(const char* p, bool f4) {
  if (f4) return std::bit_cast<float>(load_le<std::uint32_t>(p));
  return std::bit_cast<double>(load_le<std::uint64_t>(p));
}

Field load_npy(const std::filesystem::path& file) {
  const std::string data = read_all(file);
  const NpyHeader h = parse_npy_header(file, data);
  if (h.descr != "<f8" && h.descr != "<f4")
    file_error(file, "unsupported dtype '" + h.descr + "' (expected '<f8' or '<f4')");
  if (h.shape.size() != 2)
    file_error(file, "array is " + std::to_string(h.shape.size()) + "-D, expected 2-D");
  const long long ny = h.shape[0], nx = h.shape[1];
  const bool f4 = h.descr == "<f4";
  const std::size_t item = f4 ? 4 : 8;
  require_sane_shape(file, ny, nx);
  const std::size_t avail = data.size() - h.data_offset;
  if (std::size_t(nx) * std::size_t(ny) * item != avail)
    file_error(file, "data size does not match shape (" + std::to_string(ny) + ", " +
                         std::to_string(nx) + ")");
  Field z(nx, ny);
  const char* p = data.data() + h.data_offset;
  for (long long j = 0; j < ny; ++j)
    for (long long i = 0; i < nx; ++i) {
      const long long k = h.fortran ? j + ny * i : i + nx * j;  // element [j][i]
      z(i, j) = npy_value(p + k * item, f4);
    }
  return z;
}

void save_npy(const std::filesystem::path& file, const Field& z) {
  std::string dict = "{'descr': '<f8', 'fortran_order': False, 'shape': (" +
                     std::to_string(z.cols()) + ", " + std::to_string(z.rows()) + "), }";
  const std::size_t total = (10 + dict.size() + 1 + 63) / 64 * 64;  // incl. newline
  dict.append(total - 10 - dict.size() - 1, ' ').push_back('\n');
  std::string out(kNpyMagic);
  out += '\x01';
  out += '\x00';
  append_le(out, std::uint16_t(dict.size()));
  out += dict;
  for (Eigen::Index k = 0; k < z.size(); ++k)  // column-major (nx, ny) == C order [j][i]
    append_le(out, std::bit_cast<std::uint64_t>(z.data()[k]));
  std::ofstream os(file, std::ios::binary | std::ios::trunc);
  if (!os.write(out.data(), std::streamsize(out.size())) || !os.flush())
    file_error(file, "cannot write");
}

// ---------------------------------------------------------------------------------------
// Whitespace-separated text: one row (constant y) per line.

std::vector<double> parse_text_row(const std::filesystem::path& file, std::string_view line,
                                   int lineno) {
  std::vector<double> row;
  std::size_t pos = 0;
  while ((pos = line.find_first_not_of(" \t\r\v\f", pos)) != line.npos) {
    const std::size_t end = std::min(line.find_first_of(" \t\r\v\f", pos), line.size());
    std::string_view tok = line.substr(pos, end - pos);
    pos = end;
    const std::string_view num = tok.starts_with('+') ? tok.substr(1) : tok;
    double v = 0;
    const auto r = std::from_chars(num.data(), num.data() + num.size(), v);
    if (r.ec != std::errc() || r.ptr != num.data() + num.size())
      file_error(file, "line " + std::to_string(lineno) + ": non-numeric value '" +
                           std::string(tok) + "'");
    if (!std::isfinite(v))
      file_error(file, "line " + std::to_string(lineno) + ": NaN or Inf value");
    row.push_back(v);
  }
  return row;
}

Field load_text(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) file_error(file, "cannot open for reading");
  std::vector<std::vector<double>> rows;
  std::string line;
  int first_line = 0;
  for (int lineno = 1; std::getline(in, line); ++lineno) {
    auto row = parse_text_row(file, std::string_view(line).substr(0, line.find('#')), lineno);
    if (row.empty()) continue;
    if (rows.empty()) first_line = lineno;
    if (!rows.empty() && row.size() != rows[0].size())
      file_error(file, "line " + std::to_string(lineno) + " has " + std::to_string(row.size()) +
                           " values, line " + std::to_string(first_line) + " has " +
                           std::to_string(rows[0].size()) + " (ragged rows)");
    rows.push_back(std::move(row));
  }
  if (in.bad()) file_error(file, "read error");
  if (rows.empty()) file_error(file, "no numbers in the file");
  Field z(Eigen::Index(rows[0].size()), Eigen::Index(rows.size()));
  for (std::size_t j = 0; j < rows.size(); ++j)
    for (std::size_t i = 0; i < rows[j].size(); ++i) z(i, j) = rows[j][i];
  return z;
}

void save_text(const std::filesystem::path& file, const Field& z) {
  std::ofstream os(file, std::ios::trunc);
  if (!os) file_error(file, "cannot open for writing");
  for (Eigen::Index j = 0; j < z.cols(); ++j) {
    for (Eigen::Index i = 0; i < z.rows(); ++i) {
      if (i) os.put(' ');
      os << format_number(z(i, j));
    }
    os.put('\n');
  }
  if (!os.flush()) file_error(file, "cannot write");
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Public API

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

Field load_height_map(const std::filesystem::path& file, const std::string& dataset) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) file_error(file, "no such file");
  try {
    const std::string ext = lower_extension(file);
    Field z = ext == ".h5" || ext == ".hdf5" ? load_h5(file, dataset)
              : ext == ".npy"                ? load_npy(file)
                                             : load_text(file);
    require_finite(file, z);
    return z;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {  // bad_alloc for absurd shapes, filesystem errors
    file_error(file, e.what());
  }
}

void save_height_map(const std::filesystem::path& file, const Field& z) {
  if (z.size() == 0) file_error(file, "refusing to write an empty height map");
  require_finite(file, z);
  const std::string ext = lower_extension(file);
  if (ext == ".h5" || ext == ".hdf5")
    save_h5(file, z);
  else if (ext == ".npy")
    save_npy(file, z);
  else
    save_text(file, z);
}

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
  return s;
}

}  // namespace fretbem
