// HalfSpace's kernel spectra: the exact cell influence coefficients (love.hpp) of the free
// (zero-padded) and the periodic grid, transformed once per grid.
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "fretbem/elastic/half_space.hpp"
#include "fretbem/elastic/kernel_samples.hpp"
#include "half_space_fft.hpp"
#include "kernel_values.hpp"

namespace fretbem {

namespace {

// The free grid's kernels sampled in real space on the padded n0 x n1 grid (row-major, as the
// transforms read them); only those the coupling needs are filled.
struct FreeSamples {
  std::vector<double> z, xx, yy, xy, zx, zy;
};

// Free boundary: kernel sampled at offsets -(n-1)..(n-1) wrapped onto the 2n-periodic padded
// grid; zero-padding the load makes the circular convolution equal the linear one.
FreeSamples sample_free(const kernel_values::Constants& c, const Grid& grid, int n0, int n1) {
  const std::size_t nr = std::size_t(n0) * n1;
  FreeSamples f;
  f.z.resize(nr);
  if (c.cerruti) f.xx.resize(nr), f.yy.resize(nr), f.xy.resize(nr);
  if (c.cross != 0.0) f.zx.resize(nr), f.zy.resize(nr);
  for (int m0 = 0; m0 < n0; ++m0) {
    const int dy = m0 <= grid.ny ? m0 : m0 - n0;
    for (int m1 = 0; m1 < n1; ++m1) {
      const int dx = m1 <= grid.nx ? m1 : m1 - n1;
      const kernel_values::Sample s = kernel_values::free_at(c, dx, dy);
      const std::size_t k = std::size_t(m0) * n1 + m1;
      f.z[k] = s.z;
      if (c.cerruti) f.xx[k] = s.xx, f.yy[k] = s.yy, f.xy[k] = s.xy;
      if (c.cross != 0.0) f.zx[k] = s.zx, f.zy[k] = s.zy;
    }
  }
  return f;
}

// What the samples depend on: the constants and the grid's shape.
struct SampleKey {
  double h, cz, ca, cb, es, cross, Lx, Ly;
  bool cerruti;
  int nx, ny, n0, n1;
  bool operator==(const SampleKey&) const = default;
};

// The last free grid's samples, kept when keep_kernel_samples is on and they fit the bound.
struct SampleCache {
  std::mutex mutex;
  bool on = false;
  std::optional<SampleKey> key;
  std::shared_ptr<const FreeSamples> samples;
  std::int64_t computed = 0;
};

SampleCache& sample_cache() {
  static SampleCache c;
  return c;
}

// 64 MiB (8 bytes a sample, 4 samples a cell on the padded grid): every grid up to n = 512,
// and n = 1024 with the analogy's single kernel; larger grids sample afresh per operator, as the
// memory guard of a run does not count a kept copy.
constexpr std::size_t kMaxKeptBytes = std::size_t(64) << 20;

std::shared_ptr<const FreeSamples> free_samples(const kernel_values::Constants& c, const Grid& grid,
                                                int n0, int n1) {
  SampleCache& cache = sample_cache();
  const SampleKey key{c.h,  c.cz,      c.ca,    c.cb,    c.es, c.cross, c.Lx,
                      c.Ly, c.cerruti, grid.nx, grid.ny, n0,   n1};
  const std::lock_guard lock(cache.mutex);
  if (cache.on && cache.key == key) return cache.samples;
  auto samples = std::make_shared<const FreeSamples>(sample_free(c, grid, n0, n1));
  ++cache.computed;
  const std::size_t kernels = 1 + (c.cerruti ? 3 : 0) + (c.cross != 0.0 ? 2 : 0);
  if (cache.on && kernels * std::size_t(n0) * n1 * sizeof(double) <= kMaxKeptBytes)
    cache.key = key, cache.samples = samples;
  return samples;
}

}  // namespace

void keep_kernel_samples(bool on) {
  SampleCache& cache = sample_cache();
  const std::lock_guard lock(cache.mutex);
  cache.on = on;
  if (!on) cache.key.reset(), cache.samples.reset();
}

std::int64_t kernel_samples_computed() {
  SampleCache& cache = sample_cache();
  const std::lock_guard lock(cache.mutex);
  return cache.computed;
}

void HalfSpace::build_free_kernels(const Material& m) {
  Fft& F = *fft_;
  const Engine<double>& E = F.builder();
  const bool cer = coupling_ != Coupling::analogy, cross = cross_ != 0.0;
  const kernel_values::Constants c(grid_, m, cer, cross_);
  const auto samples = free_samples(c, grid_, E.n0, E.n1);
  kz_space_ = Eigen::Map<const Eigen::ArrayXXd>(samples->z.data(), E.n1, E.n0);
  self_ = kz_space_(0, 0);
  F.sz = F.spectrum_of(samples->z.data());
  if (cer) {
    F.sxx = F.spectrum_of(samples->xx.data());
    F.syy = F.spectrum_of(samples->yy.data());
    F.sxy = F.spectrum_of(samples->xy.data());
  }
  if (cross) {
    F.szx = F.spectrum_of(samples->zx.data(), 1);
    F.szy = F.spectrum_of(samples->zy.data(), 1);
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
