#include "fretbem/elastic/half_space.hpp"

#include <fftw3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>
#include <mutex>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "fretbem/core/errors.hpp"
#include "fretbem/elastic/fft_wisdom.hpp"
#include "fretbem/elastic/love.hpp"

namespace fretbem {

namespace {

// FFTW's planner is process-wide and not thread-safe: plan creation is serialised here (one
// lock for both precisions keeps it simple; planning is rare).
std::mutex& planner_mutex() {
  static std::mutex m;
  return m;
}

// The FFTW entry points of one precision: fftw_* for double, fftwf_* for float.
template <class Real>
struct Fftw;

template <>
struct Fftw<double> {
  using Real = double;
  using Complex = fftw_complex;
  using Plan = fftw_plan;
  static void* malloc(std::size_t bytes) { return fftw_malloc(bytes); }
  static void free(void* p) { fftw_free(p); }
  static void init_threads() { fftw_init_threads(); }
  static void plan_with_nthreads(int n) { fftw_plan_with_nthreads(n); }
  static Plan plan_r2c(int n0, int n1, double* in, Complex* out, unsigned flags) {
    return fftw_plan_dft_r2c_2d(n0, n1, in, out, flags);
  }
  static Plan plan_c2r(int n0, int n1, Complex* in, double* out, unsigned flags) {
    return fftw_plan_dft_c2r_2d(n0, n1, in, out, flags);
  }
  static void r2c(Plan p, double* in, Complex* out) { fftw_execute_dft_r2c(p, in, out); }
  static void c2r(Plan p, Complex* in, double* out) { fftw_execute_dft_c2r(p, in, out); }
  // howmany 1-d transforms of length n: rows (stride 1, distance dist) or columns (stride
  // `stride`, distance 1).
  static Plan plan_rows_r2c(int n, int howmany, double* in, int idist, Complex* out, int odist,
                            unsigned flags) {
    return fftw_plan_many_dft_r2c(1, &n, howmany, in, nullptr, 1, idist, out, nullptr, 1, odist,
                                  flags);
  }
  static Plan plan_rows_c2r(int n, int howmany, Complex* in, int idist, double* out, int odist,
                            unsigned flags) {
    return fftw_plan_many_dft_c2r(1, &n, howmany, in, nullptr, 1, idist, out, nullptr, 1, odist,
                                  flags);
  }
  static Plan plan_columns(int n, int howmany, Complex* in, Complex* out, int stride, int sign,
                           unsigned flags) {
    return fftw_plan_many_dft(1, &n, howmany, in, nullptr, stride, 1, out, nullptr, stride, 1, sign,
                              flags);
  }
  static void execute(Plan p) { fftw_execute(p); }
  static void destroy(Plan p) { fftw_destroy_plan(p); }
};

template <>
struct Fftw<float> {
  using Real = float;
  using Complex = fftwf_complex;
  using Plan = fftwf_plan;
  static void* malloc(std::size_t bytes) { return fftwf_malloc(bytes); }
  static void free(void* p) { fftwf_free(p); }
  static void init_threads() { fftwf_init_threads(); }
  static void plan_with_nthreads(int n) { fftwf_plan_with_nthreads(n); }
  static Plan plan_r2c(int n0, int n1, float* in, Complex* out, unsigned flags) {
    return fftwf_plan_dft_r2c_2d(n0, n1, in, out, flags);
  }
  static Plan plan_c2r(int n0, int n1, Complex* in, float* out, unsigned flags) {
    return fftwf_plan_dft_c2r_2d(n0, n1, in, out, flags);
  }
  static void r2c(Plan p, float* in, Complex* out) { fftwf_execute_dft_r2c(p, in, out); }
  static void c2r(Plan p, Complex* in, float* out) { fftwf_execute_dft_c2r(p, in, out); }
  static Plan plan_rows_r2c(int n, int howmany, float* in, int idist, Complex* out, int odist,
                            unsigned flags) {
    return fftwf_plan_many_dft_r2c(1, &n, howmany, in, nullptr, 1, idist, out, nullptr, 1, odist,
                                   flags);
  }
  static Plan plan_rows_c2r(int n, int howmany, Complex* in, int idist, float* out, int odist,
                            unsigned flags) {
    return fftwf_plan_many_dft_c2r(1, &n, howmany, in, nullptr, 1, idist, out, nullptr, 1, odist,
                                   flags);
  }
  static Plan plan_columns(int n, int howmany, Complex* in, Complex* out, int stride, int sign,
                           unsigned flags) {
    return fftwf_plan_many_dft(1, &n, howmany, in, nullptr, stride, 1, out, nullptr, stride, 1,
                               sign, flags);
  }
  static void execute(Plan p) { fftwf_execute(p); }
  static void destroy(Plan p) { fftwf_destroy_plan(p); }
};

template <class Real>
void init_fftw_threads() {
  static std::once_flag flag;  // one per precision: the two libraries keep separate state
  std::call_once(flag, [] { Fftw<Real>::init_threads(); });
}

template <class Real>
struct FftwDeleter {
  void operator()(void* p) const { Fftw<Real>::free(p); }
};
template <class Real, class T>
using FftwBuffer = std::unique_ptr<T[], FftwDeleter<Real>>;

template <class Real, class T>
FftwBuffer<Real, T> fftw_alloc(std::size_t n) {
  auto* p = static_cast<T*>(Fftw<Real>::malloc(sizeof(T) * n));
  if (!p) throw std::bad_alloc();
  return FftwBuffer<Real, T>(p);
}

double sinc(double x) {
  return x == 0.0 ? 1.0 : std::sin(x) / x;
}

// A real kernel spectrum in the engine's precision: value k is scale * v[k]. In double the
// scale is 1 and v the spectrum itself (bit-for-bit the old arithmetic). In float v is
// normalised to a largest magnitude of 1 and the scale applied when results are copied out in
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
    const std::size_t ns = std::size_t(n0) * nc;
    const Real* sv = s.v.data();
    for (std::size_t k = 0; k < ns; ++k) c1[k][0] *= sv[k], c1[k][1] *= sv[k];
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
    const std::size_t ns = std::size_t(n0) * nc;
    const Real* sv = s.v.data();
    for (std::size_t k = 0; k < ns; ++k) c1[k][0] *= sv[k], c1[k][1] *= sv[k];
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
    const std::size_t ns = std::size_t(n0) * nc;
    for (std::size_t k = 0; k < ns; ++k) {
      for (int c = 0; c < 2; ++c) {
        const Real a = c1[k][c], b = c2[k][c];
        c3[k][c] = sxx.v[k] * a + sxy.v[k] * b;
        c1[k][c] = sxy.v[k] * a + syy.v[k] * b;
      }
    }
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

}  // namespace

// The engine of the chosen precision. Kernels are always built with a double engine (exact
// spectra); a float32 HalfSpace then swaps it for a float engine.
struct HalfSpace::Fft {
  std::variant<std::unique_ptr<Engine<double>>, std::unique_ptr<Engine<float>>> engine;
  // Double spectra of the kernel build, dropped once the engine holds its own copies.
  std::vector<double> sz, sxx, syy, sxy, szx, szy;

  Engine<double>& builder() { return *std::get<0>(engine); }
  template <class F>
  void visit(F&& f) {
    std::visit([&](auto& e) { f(*e); }, engine);
  }

  // Spectrum of a real even kernel stored row-major in k (n0*n1): its real part, divided by n.
  // part = 1: the imaginary part, the spectrum of the odd part of the kernel (cross kernels).
  std::vector<double> spectrum_of(const double* k, int part = 0) {
    Engine<double>& E = builder();
    const std::size_t nr = std::size_t(E.n0) * E.n1;
    std::copy_n(k, nr, E.rin.get());
    E.r2c(E.c1.get());
    std::fill(E.rin.get(), E.rin.get() + nr, 0.0);
    std::vector<double> s(std::size_t(E.n0) * E.nc);
    const double inv_n = 1.0 / (double(E.n0) * E.n1);
    for (std::size_t i = 0; i < s.size(); ++i) s[i] = E.c1[i][part] * inv_n;
    return s;
  }
};

HalfSpace::HalfSpace(const Grid& grid, const Material& material, Coupling coupling, FftOptions fft)
    : grid_(grid), coupling_(coupling), precision_(fft.precision) {
  if (grid.nx < 1 || grid.ny < 1 || !(grid.h > 0))
    throw std::invalid_argument("HalfSpace: empty grid");
  const int f = grid.periodic ? 1 : 2;
  const int n0 = f * grid.ny, n1 = f * grid.nx;
  const bool single = fft.precision == FftPrecision::float32;
  // The kernel spectra take a handful of transforms: a float32 operator builds them with a
  // throw-away ESTIMATE double plan rather than measuring plans it will not keep.
  FftOptions build = fft;
  if (single) build.measure = false;
  fft_ = std::make_unique<Fft>();
  // Zero padding (free boundary): a field fills the first ny of the n0 rows.
  const int rows = grid.periodic ? n0 : grid.ny;
  fft_->engine = std::make_unique<Engine<double>>(n0, n1, rows, build);
  ratio_ = material.E_star() / material.G_star();
  if (coupling == Coupling::coupled) cross_ = material.cross_compliance();
  if (grid.periodic)
    build_periodic_kernels(material);
  else
    build_free_kernels(material);
  Fft& F = *fft_;
  max_eig_ = *std::max_element(F.sz.begin(), F.sz.end()) * double(n0) * n1;
  const bool cer = coupling_ != Coupling::analogy;
  auto install = [&](auto& E) {
    using Real = typename std::remove_reference_t<decltype(E)>::Api::Real;
    E.sz = make_spectrum<Real>(F.sz, spectrum_scale<Real>({&F.sz}));
    if (cer) {
      const double sc = spectrum_scale<Real>({&F.sxx, &F.syy, &F.sxy});
      E.sxx = make_spectrum<Real>(F.sxx, sc);
      E.syy = make_spectrum<Real>(F.syy, sc);
      E.sxy = make_spectrum<Real>(F.sxy, sc);
    }
    if (cross_ != 0.0) {
      const double sc = spectrum_scale<Real>({&F.szx, &F.szy});
      E.szx = make_spectrum<Real>(F.szx, sc);
      E.szy = make_spectrum<Real>(F.szy, sc);
    }
  };
  if (single) {
    F.engine = std::unique_ptr<Engine<float>>();  // free the double buffers first
    auto E = std::make_unique<Engine<float>>(n0, n1, rows, fft);
    install(*E);
    F.engine = std::move(E);
  } else {
    install(F.builder());
  }
  for (auto* v : {&F.sz, &F.sxx, &F.syy, &F.sxy, &F.szx, &F.szy}) *v = {}, v->shrink_to_fit();
}

HalfSpace::~HalfSpace() = default;

double HalfSpace::min_tolerance() const {
  return precision_ == FftPrecision::float32 ? kFloatFftMinTolerance : 0.0;
}

void HalfSpace::require_tolerance(double tolerance, const char* solver) const {
  if (tolerance >= min_tolerance()) return;
  std::ostringstream msg;
  msg << solver << ": tolerance " << tolerance
      << " is below what float FFTs can reach (round-off floor; smallest allowed "
      << min_tolerance() << "): raise solver.tolerance or use solver.fft_precision = double";
  throw InputError(msg.str());
}

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

void HalfSpace::normal(const Field& p, Field& uz) {
  fft_->visit([&](auto& E) { E.convolve(E.sz, p, uz, grid_.nx, grid_.ny); });
  ++convolutions_;
}

void HalfSpace::normal_inverse(const Field& r, Field& z) {
  fft_->visit([&](auto& E) {
    if (E.sz_inv.empty()) E.build_inverse();
    E.convolve(E.sz_inv, r, z, grid_.nx, grid_.ny);
  });
  ++convolutions_;
}

void HalfSpace::tangential_analogy(const Field& t, Field& u) {
  fft_->visit([&](auto& E) { E.convolve(E.sz, t, u, grid_.nx, grid_.ny, ratio_); });
  ++convolutions_;
}

void HalfSpace::tangential(const Field& tx, const Field& ty, Field& ux, Field& uy) {
  if (coupling_ == Coupling::analogy) {
    tangential_analogy(tx, ux);
    tangential_analogy(ty, uy);
    return;
  }
  fft_->visit([&](auto& E) { E.convolve_pair(tx, ty, ux, uy, grid_.nx, grid_.ny); });
  convolutions_ += 2;
}

void HalfSpace::normal_of_traction(const Field& tx, const Field& ty, Field& uz) {
  if (!cross_coupled()) throw std::logic_error("normal_of_traction: no normal-tangential coupling");
  fft_->visit([&](auto& E) { E.convolve_cross_normal(tx, ty, uz, grid_.nx, grid_.ny); });
  convolutions_ += 2;  // three transforms: counted as the Cerruti pair's four, rounded up
}

void HalfSpace::tangential_of_pressure(const Field& p, Field& ux, Field& uy) {
  if (!cross_coupled())
    throw std::logic_error("tangential_of_pressure: no normal-tangential coupling");
  fft_->visit([&](auto& E) { E.convolve_cross_tangential(p, ux, uy, grid_.nx, grid_.ny); });
  convolutions_ += 2;
}

// The direct summation streams the kernel at one multiply-add per element: compiled twice, for
// AVX2 and the baseline, and picked at load time (GCC function multiversioning). AVX2 without
// FMA does the same multiply and add per element as the baseline, so both give the same bits;
// measured by bench_convolution per node: 89 -> 48 us at n = 512, 17 -> 10 us at 256. An
// AVX-512 clone was no faster (the kernel rows come from L2/L3) and would fuse them (FMA).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define FRETBEM_SIMD_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define FRETBEM_SIMD_CLONES
#endif

FRETBEM_SIMD_CLONES void HalfSpace::add_sparse(const Eigen::ArrayXXd& kernel, double scale,
                                               std::span<const std::int64_t> idx,
                                               std::span<const double> val, Field& u) const {
  const int nx = grid_.nx, ny = grid_.ny, N1 = int(kernel.rows()), N0 = int(kernel.cols());
  // Row by row, all nodes per row: the row of u stays in L1 across the nodes (node by node,
  // the whole of u streamed through the cache once per node). Each element still receives the
  // nodes' terms in node order, so the sums are bit for bit the node-by-node ones.
  for (int j = 0; j < ny; ++j) {
    double* urow = u.data() + std::size_t(j) * nx;
    for (std::size_t n = 0; n < idx.size(); ++n) {
      const int si = int(idx[n] % nx), sj = int(idx[n] / nx);
      const double v = scale * val[n];
      const int m0 = ((j - sj) % N0 + N0) % N0;
      const double* krow = kernel.data() + std::size_t(m0) * N1;
      // Offsets i - si >= 0 map to m1 = i - si; negative ones wrap to N1 + i - si.
      for (int i = 0; i < si; ++i) urow[i] += v * krow[N1 + i - si];
      for (int i = si; i < nx; ++i) urow[i] += v * krow[i - si];
    }
  }
}

// Targets grouped by grid row (sorted indices are): per row and node one kernel row, read at
// the targets' offsets. Each target receives the nodes' terms in node order, as in add_sparse.
void HalfSpace::add_sparse_at(const Eigen::ArrayXXd& kernel, double scale,
                              std::span<const std::int64_t> idx, std::span<const double> val,
                              std::span<const std::int64_t> targets, Field& u) const {
  const int nx = grid_.nx, N1 = int(kernel.rows()), N0 = int(kernel.cols());
  double* ud = u.data();
  for (std::size_t a = 0; a < targets.size();) {
    const int j = int(targets[a] / nx);
    std::size_t b = a;
    while (b < targets.size() && targets[b] / nx == j) ++b;
    for (std::size_t n = 0; n < idx.size(); ++n) {
      const int si = int(idx[n] % nx), sj = int(idx[n] / nx);
      const double v = scale * val[n];
      const int m0 = ((j - sj) % N0 + N0) % N0;
      const double* krow = kernel.data() + std::size_t(m0) * N1;
      const std::int64_t base = std::int64_t(j) * nx + si;
      for (std::size_t t = a; t < b; ++t) {
        const int m1 = int(targets[t] - base);  // i - si, in (-nx, nx)
        ud[targets[t]] += v * krow[m1 < 0 ? m1 + N1 : m1];
      }
    }
    a = b;
  }
}

std::size_t HalfSpace::sparse_limit() const {
  // Below the break-even of one direct-summation node against one convolution, measured by
  // bench_convolution with the AVX2 summation (one core, pruned ESTIMATE plans): 76 nodes at
  // n = 128, 88 at 256, 159 at 512. The convolution's share of cache misses grows from 512 on,
  // so the break-even grows faster than log n there; 0.28 n follows it with 10 % to spare.
  const double side = std::sqrt(double(grid_.nx) * double(grid_.ny));
  return std::size_t(std::max({24.0, 0.28 * side, std::min(0.55 * side, 80.0)}));
}

void HalfSpace::normal_add_sparse(std::span<const std::int64_t> idx, std::span<const double> val,
                                  Field& uz) const {
  add_sparse(kz_space_, 1.0, idx, val, uz);
}

void HalfSpace::tangential_add_sparse(std::span<const std::int64_t> idx,
                                      std::span<const double> val, Field& u) const {
  add_sparse(kz_space_, ratio_, idx, val, u);
}

void HalfSpace::tangential_add_sparse_at(std::span<const std::int64_t> idx,
                                         std::span<const double> val,
                                         std::span<const std::int64_t> targets, Field& u) const {
  add_sparse_at(kz_space_, ratio_, idx, val, targets, u);
}

}  // namespace fretbem
