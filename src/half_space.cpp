#include "fretbem/half_space.hpp"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <mutex>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "fretbem/love.hpp"

namespace fretbem {

namespace {

// FFTW's planner is process-wide and not thread-safe: plan creation is serialised here.
std::mutex& planner_mutex() {
  static std::mutex m;
  return m;
}

void init_fftw_threads() {
  static std::once_flag flag;
  std::call_once(flag, [] { fftw_init_threads(); });
}

template <class T>
struct FftwDeleter {
  void operator()(T* p) const { fftw_free(p); }
};
template <class T>
using FftwBuffer = std::unique_ptr<T[], FftwDeleter<T>>;

template <class T>
FftwBuffer<T> fftw_alloc(std::size_t n) {
  auto* p = static_cast<T*>(fftw_malloc(sizeof(T) * n));
  if (!p) throw std::bad_alloc();
  return FftwBuffer<T>(p);
}

double sinc(double x) {
  return x == 0.0 ? 1.0 : std::sin(x) / x;
}

}  // namespace

// Plans and buffers for real convolutions on an n0 x n1 (row-major, n1 contiguous) array.
struct HalfSpace::Fft {
  int n0, n1, nc;  // nc = n1/2 + 1 complex columns
  FftwBuffer<double> rin, rout;
  FftwBuffer<fftw_complex> c1, c2, c3;
  fftw_plan forward = nullptr, inverse = nullptr;
  // Kernel spectra, real (the kernels are even), pre-divided by n0*n1.
  std::vector<double> sz, sxx, syy, sxy;
  std::vector<double> sz_inv;  // 1 / spectrum, pre-divided by n0*n1; built on first use

  Fft(int n0_, int n1_, FftOptions opt) : n0(n0_), n1(n1_), nc(n1_ / 2 + 1) {
    const std::size_t nr = std::size_t(n0) * n1, ncx = std::size_t(n0) * nc;
    rin = fftw_alloc<double>(nr);
    rout = fftw_alloc<double>(nr);
    c1 = fftw_alloc<fftw_complex>(ncx);
    c2 = fftw_alloc<fftw_complex>(ncx);
    c3 = fftw_alloc<fftw_complex>(ncx);
    std::fill(rin.get(), rin.get() + nr, 0.0);
    init_fftw_threads();
    std::lock_guard lock(planner_mutex());
    fftw_plan_with_nthreads(std::max(1, opt.threads));
    // r2c must preserve its input: the zero padding of rin is written once and relied on.
    const unsigned rigour = opt.measure ? FFTW_MEASURE : FFTW_ESTIMATE;
    forward = fftw_plan_dft_r2c_2d(n0, n1, rin.get(), c1.get(), rigour | FFTW_PRESERVE_INPUT);
    inverse = fftw_plan_dft_c2r_2d(n0, n1, c1.get(), rout.get(), rigour | FFTW_DESTROY_INPUT);
    if (!forward || !inverse) throw std::runtime_error("FFTW could not create a plan");
    std::fill(rin.get(), rin.get() + nr, 0.0);  // MEASURE may have scribbled on it
  }
  ~Fft() {
    std::lock_guard lock(planner_mutex());
    if (forward) fftw_destroy_plan(forward);
    if (inverse) fftw_destroy_plan(inverse);
  }

  // Copies an (nx, ny) field into the top-left block of rin (padding stays zero).
  void load(const Field& f) {
    const int nx = int(f.rows()), ny = int(f.cols());
    for (int j = 0; j < ny; ++j)
      std::copy_n(f.data() + std::size_t(j) * nx, nx, rin.get() + std::size_t(j) * n1);
  }
  void store(Field& f) const {
    const int nx = int(f.rows()), ny = int(f.cols());
    for (int j = 0; j < ny; ++j)
      std::copy_n(rout.get() + std::size_t(j) * n1, nx, f.data() + std::size_t(j) * nx);
  }
  void r2c(fftw_complex* out) { fftw_execute_dft_r2c(forward, rin.get(), out); }
  void c2r(fftw_complex* in) { fftw_execute_dft_c2r(inverse, in, rout.get()); }

  // Spectrum of a real even kernel stored row-major in k (n0*n1): its real part, divided by n.
  std::vector<double> spectrum_of(const double* k) {
    std::copy_n(k, std::size_t(n0) * n1, rin.get());
    r2c(c1.get());
    std::fill(rin.get(), rin.get() + std::size_t(n0) * n1, 0.0);
    std::vector<double> s(std::size_t(n0) * nc);
    const double inv_n = 1.0 / (double(n0) * n1);
    for (std::size_t i = 0; i < s.size(); ++i) s[i] = c1[i][0] * inv_n;
    return s;
  }
};

HalfSpace::HalfSpace(const Grid& grid, const Material& material, Coupling coupling, FftOptions fft)
    : grid_(grid), coupling_(coupling) {
  if (grid.nx < 1 || grid.ny < 1 || !(grid.h > 0))
    throw std::invalid_argument("HalfSpace: empty grid");
  const int f = grid.periodic ? 1 : 2;
  fft_ = std::make_unique<Fft>(f * grid.ny, f * grid.nx, fft);
  ratio_ = material.E_star() / material.G_star();
  if (grid.periodic)
    build_periodic_kernels(material);
  else
    build_free_kernels(material);
  max_eig_ = *std::max_element(fft_->sz.begin(), fft_->sz.end()) * double(fft_->n0) * fft_->n1;
}

HalfSpace::~HalfSpace() = default;

// Free boundary: kernel sampled at offsets -(n-1)..(n-1) wrapped onto the 2n-periodic padded
// grid; zero-padding the load makes the circular convolution equal the linear one.
void HalfSpace::build_free_kernels(const Material& m) {
  Fft& F = *fft_;
  const double h = grid_.h, a = 0.5 * h;
  const double cz = 1.0 / (std::numbers::pi * m.E_star());
  const bool cer = coupling_ == Coupling::cerruti;
  const double ca = m.cerruti_a(), cb = m.cerruti_b();
  const std::size_t nr = std::size_t(F.n0) * F.n1;
  kz_space_.resize(F.n1, F.n0);
  std::vector<double> kxx(cer ? nr : 0), kyy(cer ? nr : 0), kxy(cer ? nr : 0);
  for (int m0 = 0; m0 < F.n0; ++m0) {
    const int dy = m0 <= grid_.ny ? m0 : m0 - F.n0;
    for (int m1 = 0; m1 < F.n1; ++m1) {
      const int dx = m1 <= grid_.nx ? m1 : m1 - F.n1;
      const double x = dx * h, y = dy * h;
      const double i1 = love::I1(x, y, a, a);
      kz_space_(m1, m0) = cz * i1;
      if (cer) {
        const std::size_t k = std::size_t(m0) * F.n1 + m1;
        kxx[k] = ca * i1 + cb * love::Ixx(x, y, a, a);
        kyy[k] = ca * i1 + cb * love::Iyy(x, y, a, a);
        kxy[k] = cb * love::Ixy(x, y, a, a);
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
}

// Periodic surface: the discrete kernel spectrum is the alias sum of the continuous symbol
// times the cell's form factor, K_d(q) = sum_k G(q_k) sinc(q_kx h/2) sinc(q_ky h/2),
// q_k = q + 2 pi k / h. The alternating tails are truncated at |k| <= 8 with half weight on the
// last term. The q = 0 mode is zero: displacements are measured from their mean.
void HalfSpace::build_periodic_kernels(const Material& m) {
  Fft& F = *fft_;
  const double h = grid_.h, pi = std::numbers::pi;
  const double Lx = grid_.length_x(), Ly = grid_.length_y();
  const bool cer = coupling_ == Coupling::cerruti;
  const double ca = m.cerruti_a(), cb = m.cerruti_b(), es = m.E_star();
  const std::size_t ns = std::size_t(F.n0) * F.nc;
  const double inv_n = 1.0 / (double(F.n0) * F.n1);
  F.sz.assign(ns, 0.0);
  if (cer) F.sxx.assign(ns, 0.0), F.syy.assign(ns, 0.0), F.sxy.assign(ns, 0.0);
  constexpr int K = 8;
  for (int m0 = 0; m0 < F.n0; ++m0) {
    const double qy0 = 2 * pi * (m0 <= F.n0 / 2 ? m0 : m0 - F.n0) / Ly;
    for (int m1 = 0; m1 < F.nc; ++m1) {
      const double qx0 = 2 * pi * m1 / Lx;
      if (m0 == 0 && m1 == 0) continue;
      double sz = 0, sxx = 0, syy = 0, sxy = 0;
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
        }
      }
      const std::size_t k = std::size_t(m0) * F.nc + m1;
      F.sz[k] = sz * inv_n;
      if (cer) F.sxx[k] = sxx * inv_n, F.syy[k] = syy * inv_n, F.sxy[k] = sxy * inv_n;
    }
  }
  // Real-space kernel (for sparse updates): inverse transform of the spectrum.
  for (std::size_t k = 0; k < ns; ++k) F.c1[k][0] = F.sz[k], F.c1[k][1] = 0.0;
  F.c2r(F.c1.get());
  kz_space_.resize(F.n1, F.n0);
  std::copy_n(F.rout.get(), std::size_t(F.n0) * F.n1, kz_space_.data());
  self_ = kz_space_(0, 0);
}

void HalfSpace::normal(const Field& p, Field& uz) {
  Fft& F = *fft_;
  F.load(p);
  F.r2c(F.c1.get());
  const std::size_t ns = std::size_t(F.n0) * F.nc;
  for (std::size_t k = 0; k < ns; ++k) F.c1[k][0] *= F.sz[k], F.c1[k][1] *= F.sz[k];
  F.c2r(F.c1.get());
  uz.resize(grid_.nx, grid_.ny);
  F.store(uz);
  ++convolutions_;
}

void HalfSpace::normal_inverse(const Field& r, Field& z) {
  Fft& F = *fft_;
  const std::size_t ns = std::size_t(F.n0) * F.nc;
  if (F.sz_inv.empty()) {
    const double n = double(F.n0) * F.n1, inv_n2 = 1.0 / (n * n);
    const double top = *std::max_element(F.sz.begin(), F.sz.end()), floor = 1e-6 * top;
    F.sz_inv.resize(ns);
    for (std::size_t k = 0; k < ns; ++k)
      // The periodic mean mode (sz = 0) gets the largest value, that of its lowest-q
      // neighbours: a zero there would make M singular and lose the mean pressure.
      F.sz_inv[k] = inv_n2 / (F.sz[k] == 0.0 ? top : std::max(F.sz[k], floor));
  }
  F.load(r);
  F.r2c(F.c1.get());
  for (std::size_t k = 0; k < ns; ++k) F.c1[k][0] *= F.sz_inv[k], F.c1[k][1] *= F.sz_inv[k];
  F.c2r(F.c1.get());
  z.resize(grid_.nx, grid_.ny);
  F.store(z);
  ++convolutions_;
}

void HalfSpace::tangential_analogy(const Field& t, Field& u) {
  normal(t, u);
  u *= ratio_;
}

void HalfSpace::tangential(const Field& tx, const Field& ty, Field& ux, Field& uy) {
  if (coupling_ == Coupling::analogy) {
    tangential_analogy(tx, ux);
    tangential_analogy(ty, uy);
    return;
  }
  Fft& F = *fft_;
  F.load(tx);
  F.r2c(F.c1.get());
  F.load(ty);
  F.r2c(F.c2.get());
  const std::size_t ns = std::size_t(F.n0) * F.nc;
  for (std::size_t k = 0; k < ns; ++k) {
    for (int c = 0; c < 2; ++c) {
      const double a = F.c1[k][c], b = F.c2[k][c];
      F.c3[k][c] = F.sxx[k] * a + F.sxy[k] * b;
      F.c1[k][c] = F.sxy[k] * a + F.syy[k] * b;
    }
  }
  ux.resize(grid_.nx, grid_.ny);
  uy.resize(grid_.nx, grid_.ny);
  F.c2r(F.c3.get());
  F.store(ux);
  F.c2r(F.c1.get());
  F.store(uy);
  convolutions_ += 2;
}

void HalfSpace::add_sparse(const Eigen::ArrayXXd& kernel, double scale,
                           std::span<const std::int64_t> idx, std::span<const double> val,
                           Field& u) const {
  const int nx = grid_.nx, ny = grid_.ny, N1 = int(kernel.rows()), N0 = int(kernel.cols());
  for (std::size_t n = 0; n < idx.size(); ++n) {
    const int si = int(idx[n] % nx), sj = int(idx[n] / nx);
    const double v = scale * val[n];
    for (int j = 0; j < ny; ++j) {
      const int m0 = ((j - sj) % N0 + N0) % N0;
      const double* krow = kernel.data() + std::size_t(m0) * N1;
      double* urow = u.data() + std::size_t(j) * nx;
      // Offsets i - si >= 0 map to m1 = i - si; negative ones wrap to N1 + i - si.
      for (int i = 0; i < si; ++i) urow[i] += v * krow[N1 + i - si];
      for (int i = si; i < nx; ++i) urow[i] += v * krow[i - si];
    }
  }
}

std::size_t HalfSpace::sparse_limit() const {
  const double side = std::sqrt(double(grid_.nx) * double(grid_.ny));
  return std::max<std::size_t>(24, std::size_t(0.5 * side));
}

void HalfSpace::normal_add_sparse(std::span<const std::int64_t> idx, std::span<const double> val,
                                  Field& uz) const {
  add_sparse(kz_space_, 1.0, idx, val, uz);
}

void HalfSpace::tangential_add_sparse(std::span<const std::int64_t> idx,
                                      std::span<const double> val, Field& u) const {
  add_sparse(kz_space_, ratio_, idx, val, u);
}

}  // namespace fretbem
