// The benchmarks' unit of time: one bare convolution (HalfSpace::normal: load, forward
// transform, spectrum product, inverse transform, store) of the padded size a run uses, with
// the same FFT plans, sampled in batches of ~20 ms between the pieces of work being timed, so
// that the unit sees the same machine state as the work it divides (a single up-front
// measurement varied 0.996-1.503 ms between rows of one loaded run; at n = 512 it varied
// 5.8-8.8 ms between runs on one quiet day). Header only, shared by bench_cycle and
// bench_monotone.
#pragma once

#include <algorithm>
#include <ctime>
#include <utility>
#include <vector>

#include "fretbem/elastic/half_space.hpp"

namespace bench {

/// Process CPU seconds (single-threaded benchmarks: CPU time excludes other processes' time).
inline double cpu_now() {
  return double(std::clock()) / CLOCKS_PER_SEC;
}

class BareConvolution {
 public:
  BareConvolution(int n, bool measure)
      : hs_(fretbem::Grid::square(n, 1.0), material(), fretbem::Coupling::analogy,
            fretbem::FftOptions{1, measure, fretbem::FftPrecision::float64}),
        p_(fretbem::Field::Random(n, n)) {
    const double cpu0 = cpu_now();
    hs_.normal(p_, u_);  // warm-up
    batch_ = std::max(1, int(0.02 / std::max(cpu_now() - cpu0, 1e-6)));
  }
  /// One sample: CPU seconds per convolution over a batch.
  void sample() {
    const double cpu0 = cpu_now();
    for (int b = 0; b < batch_; ++b) hs_.normal(p_, u_);
    samples_.push_back((cpu_now() - cpu0) / batch_);
  }
  /// The samples taken since the last call, and a fresh start.
  std::vector<double> take() { return std::exchange(samples_, {}); }

 private:
  static fretbem::Material material() {
    fretbem::Material m;
    m.body1 = {1.0, 0.3};
    return m;
  }
  fretbem::HalfSpace hs_;
  fretbem::Field p_, u_;
  int batch_ = 1;
  std::vector<double> samples_;
};

}  // namespace bench
