// The FFT convolution engine of one precision: plans, work buffers and the kernel spectra of
// a (padded) grid, with the convolutions HalfSpace offers. Internal to src/elastic.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "fftw_api.hpp"
#include "fretbem/elastic/fft_wisdom.hpp"
#include "fretbem/elastic/grid.hpp"
#include "fretbem/elastic/half_space.hpp"

namespace fretbem::fft_detail {

// A real kernel spectrum in the engine's precision: value k is scale * v[k]. In double the
// scale is 1 and v the spectrum itself (the spectrum as the double transform gives it). In float v
// is normalised to a largest magnitude of 1 and the scale applied when results are copied out in
// double: compliances pre-divided by the transform size reach 1e-27 m/Pa for steel on fine
// grids, too close to float's smallest normal number (1.2e-38) for comfort.
template <class Real>
struct Spectrum {
  std::vector<Real> v;
  double scale = 1.0;
  bool empty() const { return v.empty(); }
};

template <class Real>
Spectrum<Real> make_spectrum(const std::vector<double>& s, double scale) {
  Spectrum<Real> out;
  out.scale = scale;
  out.v.resize(s.size());
  for (std::size_t k = 0; k < s.size(); ++k) out.v[k] = Real(s[k] / scale);
  return out;
}

template <class Real>
double spectrum_scale(std::initializer_list<const std::vector<double>*> spectra) {
  if constexpr (std::is_same_v<Real, double>) return 1.0;
  double top = 0.0;
  for (const auto* s : spectra)
    for (double x : *s) top = std::max(top, std::abs(x));
  return top > 0.0 ? top : 1.0;
}

// c[k] *= s[k] for the first ns wave numbers: a convolution with a real kernel spectrum.
template <class Real, class Complex>
void multiply_spectrum(std::size_t ns, const Spectrum<Real>& s, Complex* c) {
  const Real* sv = s.v.data();
  for (std::size_t k = 0; k < ns; ++k) c[k][0] *= sv[k], c[k][1] *= sv[k];
}

// (x, y) = [sxx sxy; sxy syy] (tx, ty) for the first ns wave numbers, with tx in c1 and ty in
// c2 on entry and x in c3, y in c1 on return: the Cerruti pair's spectral product.
template <class Real, class Complex>
void multiply_cerruti(std::size_t ns, const Spectrum<Real>& sxx, const Spectrum<Real>& sxy,
                      const Spectrum<Real>& syy, Complex* c1, const Complex* c2, Complex* c3) {
  for (std::size_t k = 0; k < ns; ++k) {
    for (int c = 0; c < 2; ++c) {
      const Real a = c1[k][c], b = c2[k][c];
      c3[k][c] = sxx.v[k] * a + sxy.v[k] * b;
      c1[k][c] = sxy.v[k] * a + syy.v[k] * b;
    }
  }
}

// Plans and buffers for real convolutions in precision Real on an n0 x n1 (row-major, n1
// contiguous) array, with the kernel spectra. Fields enter and leave as double.
//
// Pruned convolution (free boundary): a field fills only the first `rows` rows of the padded
// array (the rest is zero padding) and only those rows of the result are kept, so the row
// transforms of the other rows are skipped: forward = `rows` row r2c + nc column DFTs, inverse
// = nc column DFTs + `rows` row c2r, 3/4 of the 2-d transform pair's work when rows = n0/2
// (measured at 2n = 512, FFTW_ESTIMATE: 0.73-0.79 of the 2-d pair's CPU; docs/performance.md).
// Same transform, so the same result up to round-off.
template <class Real>
struct Engine {
  using Api = Fftw<Real>;
  using Complex = typename Api::Complex;
  using Plan = typename Api::Plan;
  int n0, n1, nc;  // nc = n1/2 + 1 complex columns
  int rows;        // rows a field occupies: n0 / 2 with zero padding, n0 periodic
  FftwBuffer<Real, Real> rin, rout;
  FftwBuffer<Real, Complex> c1, c2, c3;
  FftwBuffer<Real, Complex> cz;  // row spectra of rin; rows >= `rows` stay zero
  Plan forward = nullptr, inverse = nullptr;
  // The pruned pair (null when rows == n0): rin -> cz rows, cz -> c1 columns, c1 columns in
  // place, c1 -> rout rows.
  Plan rows_forward = nullptr, columns_forward = nullptr, columns_inverse = nullptr,
       rows_inverse = nullptr;
  Spectrum<Real> sz, sxx, syy, sxy;  // Cerruti spectra share one scale (they are mixed)
  Spectrum<Real> sz_inv;             // 1 / spectrum, built on first use
  // Normal-tangential cross kernels: odd, so their spectra are imaginary; v holds Im / n.
  Spectrum<Real> szx, szy;

  Engine(int n0_, int n1_, int rows_, FftOptions opt)
      : n0(n0_), n1(n1_), nc(n1_ / 2 + 1), rows(rows_) {
    const std::size_t nr = std::size_t(n0) * n1, ncx = std::size_t(n0) * nc;
    rin = fftw_alloc<Real, Real>(nr);
    rout = fftw_alloc<Real, Real>(nr);
    c1 = fftw_alloc<Real, Complex>(ncx);
    c2 = fftw_alloc<Real, Complex>(ncx);
    c3 = fftw_alloc<Real, Complex>(ncx);
    if (pruned()) cz = fftw_alloc<Real, Complex>(ncx);
    std::fill(rin.get(), rin.get() + nr, Real(0));
    init_fftw_threads<Real>();
    std::lock_guard lock(planner_mutex());
    Api::plan_with_nthreads(std::max(1, opt.threads));
    if (opt.measure)
      plan_measured();
    else
      plan(FFTW_ESTIMATE);
    if (!planned()) throw std::runtime_error("FFTW could not create a plan");
    std::fill(rin.get(), rin.get() + nr, Real(0));  // MEASURE may have scribbled on it
    if (pruned()) std::fill_n(&cz[0][0], 2 * ncx, Real(0));
  }
  bool pruned() const { return rows < n0; }
  std::array<Plan*, 6> plans() {
    return {&forward, &inverse, &rows_forward, &columns_forward, &columns_inverse, &rows_inverse};
  }
  bool planned() {
    if (!forward || !inverse) return false;
    return !pruned() || (rows_forward && columns_forward && columns_inverse && rows_inverse);
  }
  void destroy_plans() {
    for (Plan* p : plans())
      if (*p) Api::destroy(*p), *p = nullptr;
  }
  // r2c must preserve its input: the zero padding of rin is written once and relied on.
  void plan(unsigned rigour) {
    forward = Api::plan_r2c(n0, n1, rin.get(), c1.get(), rigour | FFTW_PRESERVE_INPUT);
    inverse = Api::plan_c2r(n0, n1, c1.get(), rout.get(), rigour | FFTW_DESTROY_INPUT);
    if (!pruned()) return;
    rows_forward =
        Api::plan_rows_r2c(n1, rows, rin.get(), n1, cz.get(), nc, rigour | FFTW_PRESERVE_INPUT);
    columns_forward = Api::plan_columns(n0, nc, cz.get(), c1.get(), nc, FFTW_FORWARD,
                                        rigour | FFTW_PRESERVE_INPUT);
    columns_inverse = Api::plan_columns(n0, nc, c1.get(), c1.get(), nc, FFTW_BACKWARD, rigour);
    rows_inverse =
        Api::plan_rows_c2r(n1, rows, c1.get(), nc, rout.get(), n1, rigour | FFTW_DESTROY_INPUT);
  }
  // MEASURE plans from the wisdom file when it has this size and thread count; measured (and
  // the file updated) otherwise. Same wisdom, same plan: results repeat bit for bit. Measuring
  // holds the file's lock, and a process that waited for it plans from what the holder saved:
  // one measured plan per size on a machine, whatever the timing of concurrent first runs.
  void plan_measured() {
    constexpr FftPrecision precision =
        std::is_same_v<Real, float> ? FftPrecision::float32 : FftPrecision::float64;
    fft_wisdom::load(precision);
    plan(FFTW_MEASURE | FFTW_WISDOM_ONLY);
    if (planned()) return;
    destroy_plans();
    const auto held = fft_wisdom::lock(precision);
    fft_wisdom::reload(precision);
    plan(FFTW_MEASURE | FFTW_WISDOM_ONLY);
    if (planned()) return;
    destroy_plans();
    plan(FFTW_MEASURE);
    fft_wisdom::save(precision);
  }
  ~Engine() {
    std::lock_guard lock(planner_mutex());
    destroy_plans();
  }
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  // Copies an (nx, ny) field into the top-left block of rin (padding stays zero).
  void load(const Field& f) {
    const int nx = int(f.rows()), ny = int(f.cols());
    for (int j = 0; j < ny; ++j) {
      const double* src = f.data() + std::size_t(j) * nx;
      Real* dst = rin.get() + std::size_t(j) * n1;
      for (int i = 0; i < nx; ++i) dst[i] = Real(src[i]);
    }
  }
  // The top-left (nx, ny) block of rout, times scale, into f.
  void store(Field& f, double scale) const {
    const int nx = int(f.rows()), ny = int(f.cols());
    for (int j = 0; j < ny; ++j) {
      const Real* src = rout.get() + std::size_t(j) * n1;
      double* dst = f.data() + std::size_t(j) * nx;
      for (int i = 0; i < nx; ++i) dst[i] = scale * double(src[i]);
    }
  }
  void r2c(Complex* out) { Api::r2c(forward, rin.get(), out); }
  void c2r(Complex* in) { Api::c2r(inverse, in, rout.get()); }

  // out = s * in (circular convolution with the kernel whose spectrum is s).
  // `factor` multiplies the result as it is copied out (the analogy's E*/G*: no extra pass).
  void convolve(const Spectrum<Real>& s, const Field& in, Field& out, int nx, int ny,
                double factor = 1.0) {
    if (pruned()) return convolve_pruned(s, in, out, nx, ny, factor);
    load(in);
    r2c(c1.get());
    multiply_spectrum(std::size_t(n0) * nc, s, c1.get());
    c2r(c1.get());
    out.resize(nx, ny);
    store(out, s.scale * factor);
  }

  // convolve() on a zero-padded field: the rows of zeros are not transformed, the rows of the
  // result that store() drops are not computed.
  void convolve_pruned(const Spectrum<Real>& s, const Field& in, Field& out, int nx, int ny,
                       double factor) {
    load(in);
    Api::execute(rows_forward);
    Api::execute(columns_forward);
    multiply_spectrum(std::size_t(n0) * nc, s, c1.get());
    Api::execute(columns_inverse);
    Api::execute(rows_inverse);
    out.resize(nx, ny);
    store(out, s.scale * factor);
  }

  // c1 = F[tx], c2 = F[ty]: the forward half of every product of a traction pair.
  void forward_pair(const Field& tx, const Field& ty) {
    load(tx);
    r2c(c1.get());
    load(ty);
    r2c(c2.get());
  }

  // (ux, uy) = [sxx sxy; sxy syy] * (tx, ty): the Cerruti pair, two transforms each way.
  void convolve_pair(const Field& tx, const Field& ty, Field& ux, Field& uy, int nx, int ny) {
    forward_pair(tx, ty);
    multiply_cerruti(std::size_t(n0) * nc, sxx, sxy, syy, c1.get(), c2.get(), c3.get());
    ux.resize(nx, ny);
    uy.resize(nx, ny);
    c2r(c3.get());
    store(ux, sxx.scale);
    c2r(c1.get());
    store(uy, sxx.scale);
  }

  // uz = F^-1[i (szx F[tx] + szy F[ty])]: the normal approach of tractions (three transforms).
  void convolve_cross_normal(const Field& tx, const Field& ty, Field& uz, int nx, int ny) {
    forward_pair(tx, ty);
    const std::size_t ns = std::size_t(n0) * nc;
    for (std::size_t k = 0; k < ns; ++k) {
      const Real re = szx.v[k] * c1[k][0] + szy.v[k] * c2[k][0];
      const Real im = szx.v[k] * c1[k][1] + szy.v[k] * c2[k][1];
      c3[k][0] = -im, c3[k][1] = re;  // times i
    }
    uz.resize(nx, ny);
    c2r(c3.get());
    store(uz, szx.scale);
  }

  // (ux, uy) = F^-1[-i (szx, szy) F[p]]: the transpose of convolve_cross_normal (the kernels
  // are odd, so transposing flips their sign).
  void convolve_cross_tangential(const Field& p, Field& ux, Field& uy, int nx, int ny) {
    load(p);
    r2c(c1.get());
    const std::size_t ns = std::size_t(n0) * nc;
    for (std::size_t k = 0; k < ns; ++k) {
      const Real re = c1[k][0], im = c1[k][1];
      c2[k][0] = szx.v[k] * im, c2[k][1] = -szx.v[k] * re;  // times -i szx
      c3[k][0] = szy.v[k] * im, c3[k][1] = -szy.v[k] * re;
    }
    ux.resize(nx, ny);
    uy.resize(nx, ny);
    c2r(c2.get());
    store(ux, szx.scale);
    c2r(c3.get());
    store(uy, szx.scale);
  }

  // The preconditioner's spectrum from sz: 1 / spectrum over n^2 (one division for the
  // inverse transform's missing 1/n, one for sz's), floored at 1e-6 of the largest value. The
  // periodic mean mode (sz = 0) gets the largest value, that of its lowest-q neighbours: a
  // zero there would make M singular and lose the mean pressure.
  void build_inverse() {
    const std::size_t ns = sz.v.size();
    const double n = double(n0) * n1, inv_n2 = 1.0 / (n * n);
    double top = 0.0;
    for (Real x : sz.v) top = std::max(top, sz.scale * double(x));
    const double floor = 1e-6 * top;
    std::vector<double> inv(ns);
    for (std::size_t k = 0; k < ns; ++k) {
      const double s = sz.scale * double(sz.v[k]);
      inv[k] = inv_n2 / (s == 0.0 ? top : std::max(s, floor));
    }
    sz_inv = make_spectrum<Real>(inv, spectrum_scale<Real>({&inv}));
  }
};

}  // namespace fretbem::fft_detail
