// The FFTW entry points of one precision (fftw_* for double, fftwf_* for float), FFTW's
// thread set-up, aligned buffers and the planner lock: what the FFT engine (fft_engine.hpp)
// is written against. Internal to src/elastic.
#pragma once

#include <fftw3.h>

#include <cstddef>
#include <memory>
#include <mutex>
#include <new>

namespace fretbem::fft_detail {

// FFTW's planner is process-wide and not thread-safe: plan creation is serialised here (one
// lock for both precisions keeps it simple; planning is rare).
inline std::mutex& planner_mutex() {
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

}  // namespace fretbem::fft_detail
