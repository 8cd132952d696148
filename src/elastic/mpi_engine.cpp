#include "mpi_engine.hpp"

#include <algorithm>
#include <chrono>
#include <mutex>
#include <stdexcept>

#include "../parallel/mpi.hpp"
#ifdef FRETBEM_MPI
#include <fftw3-mpi.h>
#endif

namespace fretbem::fft_detail {

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Rows in both blocks, and below `limit` (the field's ny: transform rows past it are padding).
RowBlock overlap(RowBlock a, RowBlock b, int limit) {
  const int first = std::max(a.first, b.first);
  const int end = std::min({a.first + a.count, b.first + b.count, limit});
  return {first, std::max(0, end - first)};
}

}  // namespace

RowBlock row_block(int ny, int rank, int ranks) {
  const int block = (ny + ranks - 1) / ranks;
  const int first = std::min(ny, rank * block);
  return {first, std::min(ny, first + block) - first};
}

MpiEngine::MpiEngine(const Communicator& comm, const Grid& grid,
                     const kernel_values::Constants& kernels)
    : comm_(comm), grid_(grid) {
  const int f = grid.periodic ? 1 : 2;
  n0 = f * grid.ny, n1 = f * grid.nx, nc = n1 / 2 + 1;
  for (int r = 0; r < comm.size(); ++r) field_.push_back(row_block(grid.ny, r, comm.size()));
  plan();
  build_kernels(kernels);
}

MpiEngine::~MpiEngine() {
  std::lock_guard lock(planner_mutex());
  for (fftw_plan p : {forward_, inverse_})
    if (p) fftw_destroy_plan(p);
}

#ifdef FRETBEM_MPI

// FFTW_ESTIMATE: every rank must choose the same plan, and a measured plan depends on timings
// that differ between ranks.
void MpiEngine::plan() {
  static std::once_flag init;
  std::call_once(init, [] { fftw_mpi_init(); });
  const MPI_Comm c = *static_cast<const MPI_Comm*>(comm_.native());
  ptrdiff_t ln0 = 0, l0 = 0, ln1 = 0, l1 = 0;
  const ptrdiff_t alloc = fftw_mpi_local_size_2d_transposed(n0, nc, c, &ln0, &l0, &ln1, &l1);
  local_n0 = ln0, local_0 = l0, local_n1 = ln1, local_1 = l1;
  rin = fftw_alloc<double, double>(2 * std::size_t(alloc));
  rout = fftw_alloc<double, double>(2 * std::size_t(alloc));
  c1 = fftw_alloc<double, fftw_complex>(alloc);
  c2 = fftw_alloc<double, fftw_complex>(alloc);
  c3 = fftw_alloc<double, fftw_complex>(alloc);
  std::vector<int> mine{int(l0), int(ln0)}, all(2 * comm_.size());
  MPI_Allgather(mine.data(), 2, MPI_INT, all.data(), 2, MPI_INT, c);
  for (int r = 0; r < comm_.size(); ++r) transform_.push_back({all[2 * r], all[2 * r + 1]});
  std::lock_guard lock(planner_mutex());
  forward_ = fftw_mpi_plan_dft_r2c_2d(n0, n1, rin.get(), c1.get(), c,
                                      FFTW_ESTIMATE | FFTW_MPI_TRANSPOSED_OUT);
  inverse_ = fftw_mpi_plan_dft_c2r_2d(n0, n1, c1.get(), rout.get(), c,
                                      FFTW_ESTIMATE | FFTW_MPI_TRANSPOSED_IN);
  if (!forward_ || !inverse_) throw std::runtime_error("FFTW-MPI could not create a plan");
}

// Field rows travel whole (nx values each), in ascending row order per peer, so that sender
// and receiver agree on the order without an index list.
void MpiEngine::move_rows(const std::vector<RowBlock>& from, const std::vector<RowBlock>& to,
                          Rows<const double> source, double scale, Rows<double> dest) {
  const int K = comm_.size(), me = comm_.rank(), nx = grid_.nx, ny = grid_.ny;
  std::vector<int> sc(K), sd(K), rc(K), rd(K);
  send_.clear();
  for (int q = 0; q < K; ++q) {
    const RowBlock o = overlap(from[me], to[q], ny);
    sd[q] = int(send_.size()), sc[q] = o.count * nx;
    for (int j = o.first; j < o.first + o.count; ++j) {
      const double* row = source.row(j);
      for (int i = 0; i < nx; ++i) send_.push_back(scale * row[i]);
    }
  }
  int total = 0;
  for (int q = 0; q < K; ++q)
    rd[q] = total, rc[q] = overlap(from[q], to[me], ny).count * nx, total += rc[q];
  recv_.resize(total);
  MPI_Alltoallv(send_.data(), sc.data(), sd.data(), MPI_DOUBLE, recv_.data(), rc.data(), rd.data(),
                MPI_DOUBLE, *static_cast<const MPI_Comm*>(comm_.native()));
  for (int q = 0; q < K; ++q) {
    const RowBlock o = overlap(from[q], to[me], ny);
    for (int j = o.first; j < o.first + o.count; ++j)
      std::copy_n(recv_.data() + rd[q] + std::size_t(j - o.first) * nx, nx, dest.row(j));
  }
}

void MpiEngine::scatter(const Field& f) {
  const auto t0 = Clock::now();
  const RowBlock mine = field_[comm_.rank()];
  std::fill_n(rin.get(), std::size_t(local_n0) * 2 * nc, 0.0);
  move_rows(field_, transform_, {f.data(), mine.first, std::size_t(grid_.nx)}, 1.0,
            {rin.get(), local_0, 2 * std::size_t(nc)});
  seconds_moving += since(t0);
}

void MpiEngine::gather(Field& f, double scale) {
  const auto t0 = Clock::now();
  const RowBlock mine = field_[comm_.rank()];
  f.resize(grid_.nx, mine.count);
  move_rows(transform_, field_, {rout.get(), local_0, 2 * std::size_t(nc)}, scale,
            {f.data(), mine.first, std::size_t(grid_.nx)});
  seconds_moving += since(t0);
}

void MpiEngine::forward(const Field& f, fftw_complex* out) {
  scatter(f);
  const auto t0 = Clock::now();
  fftw_mpi_execute_dft_r2c(forward_, rin.get(), out);
  seconds_transforming += since(t0);
}

void MpiEngine::inverse(fftw_complex* in, Field& f, double scale) {
  const auto t0 = Clock::now();
  fftw_mpi_execute_dft_c2r(inverse_, in, rout.get());
  seconds_transforming += since(t0);
  gather(f, scale);
}

// The r2c transform's transpose: n0 x nc complex values (2 doubles each), out of place.
double MpiEngine::transpose_seconds(int repeats) {
  const MPI_Comm c = *static_cast<const MPI_Comm*>(comm_.native());
  fftw_plan t;
  {
    std::lock_guard lock(planner_mutex());
    t = fftw_mpi_plan_many_transpose(n0, nc, 2, FFTW_MPI_DEFAULT_BLOCK, FFTW_MPI_DEFAULT_BLOCK,
                                     &c1[0][0], &c2[0][0], c, FFTW_ESTIMATE);
  }
  std::vector<double> s;
  for (int r = 0; r < repeats; ++r) {
    MPI_Barrier(c);
    const auto t0 = Clock::now();
    fftw_execute(t);
    s.push_back(comm_.max(since(t0)));
  }
  {
    std::lock_guard lock(planner_mutex());
    fftw_destroy_plan(t);
  }
  std::sort(s.begin(), s.end());
  return s.empty() ? 0.0 : s[s.size() / 2];
}

#else

double MpiEngine::transpose_seconds(int) {
  return 0.0;
}
void MpiEngine::plan() {
  throw std::runtime_error(
      "this fretbem was built without MPI (-DFRETBEM_MPI=OFF): no distributed grid");
}
void MpiEngine::scatter(const Field&) {}
void MpiEngine::gather(Field&, double) {}
void MpiEngine::forward(const Field&, fftw_complex*) {}
void MpiEngine::inverse(fftw_complex*, Field&, double) {}

#endif

// One kernel's spectrum in the transposed layout (x wave numbers local, every y wave number),
// real part over the transform size; which = 0..3: z, xx, yy, xy. The rows a rank transforms
// are filled with the kernel wrapped onto the 2n-periodic padded grid (half_space_kernels.cpp).
std::vector<double> MpiEngine::spectrum_of_rows(const kernel_values::Constants& c, int which) {
  std::fill_n(rin.get(), std::size_t(local_n0) * 2 * nc, 0.0);
  for (long r = 0; r < local_n0; ++r) {
    const int m0 = int(local_0 + r), dy = m0 <= grid_.ny ? m0 : m0 - n0;
    for (int m1 = 0; m1 < n1; ++m1) {
      const int dx = m1 <= grid_.nx ? m1 : m1 - n1;
      const kernel_values::Sample s = kernel_values::free_at(c, dx, dy);
      const double v[] = {s.z, s.xx, s.yy, s.xy};
      rin[std::size_t(r) * 2 * nc + m1] = v[which];
    }
  }
#ifdef FRETBEM_MPI
  fftw_mpi_execute_dft_r2c(forward_, rin.get(), c1.get());
#endif
  const std::size_t ns = std::size_t(local_n1) * n0;
  const double inv_n = 1.0 / (double(n0) * n1);
  std::vector<double> s(ns);
  for (std::size_t k = 0; k < ns; ++k) s[k] = c1[k][0] * inv_n;
  return s;
}

void MpiEngine::build_kernels(const kernel_values::Constants& c) {
  const std::size_t ns = std::size_t(local_n1) * n0;
  std::vector<double> s[4];
  if (grid_.periodic) {
    const double inv_n = 1.0 / (double(n0) * n1);
    for (auto& v : s) v.assign(c.cerruti ? ns : 0, 0.0);
    s[0].assign(ns, 0.0);
    for (long k1 = 0; k1 < local_n1; ++k1)
      for (int m0 = 0; m0 < n0; ++m0) {
        const auto v = kernel_values::periodic_at(c, m0, int(local_1 + k1), n0, n1);
        const std::size_t k = std::size_t(k1) * n0 + m0;
        s[0][k] = v.z * inv_n;
        if (c.cerruti) s[1][k] = v.xx * inv_n, s[2][k] = v.yy * inv_n, s[3][k] = v.xy * inv_n;
      }
  } else {
    for (int w = 0; w < (c.cerruti ? 4 : 1); ++w) s[w] = spectrum_of_rows(c, w);
  }
  sz = make_spectrum<double>(s[0], 1.0);
  if (c.cerruti) {
    sxx = make_spectrum<double>(s[1], 1.0);
    syy = make_spectrum<double>(s[2], 1.0);
    sxy = make_spectrum<double>(s[3], 1.0);
  }
  double top = 0.0;
  for (double x : s[0]) top = std::max(top, x);
  max_eig_ = comm_.max(top) * double(n0) * n1;
  if (!grid_.periodic) {
    self_ = kernel_values::free_at(c, 0, 0).z;
    return;
  }
  // Periodic: K_z(0,0) is the inverse transform of the spectrum at the origin, on rank 0.
  for (std::size_t k = 0; k < ns; ++k) c1[k][0] = s[0][k], c1[k][1] = 0.0;
#ifdef FRETBEM_MPI
  fftw_mpi_execute_dft_c2r(inverse_, c1.get(), rout.get());
#endif
  double origin[] = {comm_.rank() == 0 ? rout[0] : 0.0};
  comm_.broadcast(origin, 0);
  self_ = origin[0];
}

void MpiEngine::convolve(const Spectrum<double>& s, const Field& in, Field& out, int, int,
                         double factor) {
  forward(in, c1.get());
  multiply_spectrum(std::size_t(local_n1) * n0, s, c1.get());
  inverse(c1.get(), out, s.scale * factor);
}

void MpiEngine::convolve_pair(const Field& tx, const Field& ty, Field& ux, Field& uy, int, int) {
  forward(tx, c1.get());
  forward(ty, c2.get());
  multiply_cerruti(std::size_t(local_n1) * n0, sxx, sxy, syy, c1.get(), c2.get(), c3.get());
  inverse(c3.get(), ux, sxx.scale);
  inverse(c1.get(), uy, sxx.scale);
}

void MpiEngine::convolve_cross_normal(const Field&, const Field&, Field&, int, int) {
  throw std::logic_error("normal-tangential cross terms are not distributed");
}

void MpiEngine::convolve_cross_tangential(const Field&, Field&, Field&, int, int) {
  throw std::logic_error("normal-tangential cross terms are not distributed");
}

// The serial Engine::build_inverse's spectrum; the largest value is the largest over all ranks.
void MpiEngine::build_inverse() {
  const double n = double(n0) * n1, inv_n2 = 1.0 / (n * n);
  double top = 0.0;
  for (double x : sz.v) top = std::max(top, x);
  top = comm_.max(top);
  const double floor = 1e-6 * top;
  std::vector<double> inv(sz.v.size());
  for (std::size_t k = 0; k < inv.size(); ++k) {
    const double s = sz.v[k];
    inv[k] = inv_n2 / (s == 0.0 ? top : std::max(s, floor));
  }
  sz_inv = make_spectrum<double>(inv, 1.0);
}

}  // namespace fretbem::fft_detail
