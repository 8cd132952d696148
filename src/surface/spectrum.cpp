#include "spectrum.hpp"

#include <cmath>
#include <mutex>
#include <string>

#include "fretbem/core/errors.hpp"

namespace fretbem::surface_detail {

namespace {

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

}  // namespace

void require_grid(const Grid& g, const char* what) {
  if (g.nx < 2 || g.ny < 2 || !(g.h > 0.0) || !std::isfinite(g.h))
    throw InputError(std::string(what) +
                     ": grid needs at least 2 x 2 cells and a positive "
                     "finite spacing");
}

bool positive_finite(double v) {
  return v > 0.0 && std::isfinite(v);
}

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

int signed_index(int k, int n) {
  return k <= n / 2 ? k : k - n;
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

}  // namespace fretbem::surface_detail
