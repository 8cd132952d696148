// The FFT convolution engine of a grid distributed over MPI ranks (FFTW-MPI, double): each
// rank owns a slab of field rows j in [first_row, first_row + rows) and a slab of the rows of
// the (padded) transform grid. Forward transforms end transposed (FFTW_MPI_TRANSPOSED_OUT:
// each rank then holds a block of x wave numbers, every y wave number) and inverse transforms
// start from that layout (FFTW_MPI_TRANSPOSED_IN), so a convolution does one global transpose
// each way instead of two. Zero padding (free boundary) puts the field in the first ny of the
// 2 ny transform rows, which FFTW-MPI gives to the first half of the ranks: the field rows are
// moved to the ranks that transform them and back (one MPI_Alltoallv each way); a periodic
// grid's slabs coincide and the move is a local copy. Internal to src/elastic.
#pragma once

#include <fftw3.h>

#include <vector>

#include "fft_engine.hpp"
#include "fretbem/elastic/grid.hpp"
#include "fretbem/parallel/communicator.hpp"
#include "kernel_values.hpp"

namespace fretbem::fft_detail {

/// A block of field rows: rows j in [first, first + count) of a grid of ny rows.
struct RowBlock {
  int first = 0;
  int count = 0;
};

/// Rows of a row-major array: row j starts at data + (j - first) * stride.
template <class T>
struct Rows {
  T* data;
  long first;
  std::size_t stride;
  T* row(int j) const { return data + std::size_t(j - first) * stride; }
};

/// The block of rank r of K when ny rows are split as FFTW-MPI splits them: ceil(ny / K) rows
/// per rank, the last ranks fewer or none.
RowBlock row_block(int ny, int rank, int ranks);

class MpiEngine {
 public:
  /// Plans and the kernel spectra of `grid` (padded 2n x 2n when free, n x n periodic).
  /// Throws std::runtime_error in a build without MPI.
  MpiEngine(const Communicator& comm, const Grid& grid, const kernel_values::Constants& kernels);
  ~MpiEngine();
  MpiEngine(const MpiEngine&) = delete;
  MpiEngine& operator=(const MpiEngine&) = delete;

  RowBlock field_rows() const { return field_[comm_.rank()]; }
  double self() const { return self_; }               ///< K_z(0,0) (m/Pa)
  double max_eigenvalue() const { return max_eig_; }  ///< largest K_z spectrum value (m/Pa)

  // The serial Engine's convolutions on local slabs (nx, field_rows().count); ny is unused.
  Spectrum<double> sz, sxx, syy, sxy, sz_inv, szx, szy;
  void convolve(const Spectrum<double>& s, const Field& in, Field& out, int nx, int ny,
                double factor = 1.0);
  void convolve_pair(const Field& tx, const Field& ty, Field& ux, Field& uy, int nx, int ny);
  void convolve_cross_normal(const Field&, const Field&, Field&, int, int);
  void convolve_cross_tangential(const Field&, Field&, Field&, int, int);
  void build_inverse();

  /// Seconds spent moving field rows between the field and transform slabs (MPI_Alltoallv),
  /// and in the transforms (FFTW-MPI, with their global transposes), since construction.
  double seconds_moving = 0.0, seconds_transforming = 0.0;
  /// Median wall seconds of one global transpose of the n0 x nc spectrum (FFTW-MPI's
  /// transpose plan, what the transforms do inside) over `repeats`. Collective.
  double transpose_seconds(int repeats);

 private:
  void plan();
  void scatter(const Field& f);         // field slab -> rin (zero elsewhere)
  void gather(Field& f, double scale);  // rout's field rows -> field slab
  // This rank's rows of `from` to the ranks whose `to` block holds them, times `scale`, and
  // the rows of its own `to` block from their owners (one MPI_Alltoallv).
  void move_rows(const std::vector<RowBlock>& from, const std::vector<RowBlock>& to,
                 Rows<const double> source, double scale, Rows<double> dest);
  void forward(const Field& f, fftw_complex* out);
  void inverse(fftw_complex* in, Field& f, double scale);
  std::vector<double> spectrum_of_rows(const kernel_values::Constants& c, int which);
  void build_kernels(const kernel_values::Constants& c);

  const Communicator& comm_;
  Grid grid_;
  int n0 = 0, n1 = 0, nc = 0;                // transform grid n0 x n1 (y, x); nc = n1 / 2 + 1
  long local_n0 = 0, local_0 = 0;            // this rank's transform rows
  long local_n1 = 0, local_1 = 0;            // this rank's x wave numbers (transposed spectrum)
  std::vector<RowBlock> field_, transform_;  // every rank's field and transform rows
  FftwBuffer<double, double> rin, rout;
  FftwBuffer<double, fftw_complex> c1, c2, c3;
  fftw_plan forward_ = nullptr, inverse_ = nullptr;
  std::vector<double> send_, recv_;
  double self_ = 0.0, max_eig_ = 0.0;
};

}  // namespace fretbem::fft_detail
