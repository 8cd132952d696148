// HalfSpace's direct sums: K * e for a sparse load e by summation with the real-space kernel,
// cheaper than a convolution for few changed nodes (sparse_limit).
#include <algorithm>
#include <cmath>

#include "fretbem/elastic/half_space.hpp"

namespace fretbem {

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
  if (comm_->distributed()) return 0;
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
