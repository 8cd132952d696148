// HalfSpace: the elastic half-space operator. Maps cell tractions (Pa) to surface
// displacements (m) at the cell centres by FFT convolution with exact cell influence
// coefficients (docs/algorithms.md, "Half-space operator"). FFTW plans, work buffers and kernel
// spectra are built once per grid.
#pragma once

#include <cstdint>
#include <memory>
#include <span>

#include "fretbem/elastic/grid.hpp"
#include "fretbem/elastic/material.hpp"
#include "fretbem/parallel/communicator.hpp"

namespace fretbem {

/// How tangential tractions load the surface.
enum class Coupling {
  analogy,  ///< Cattaneo–Mindlin analogy: u_t = (E*/G*) K_z * tau, componentwise (default)
  cerruti,  ///< full Cerruti cell coefficients, with the x-y cross terms
  /// Cerruti, plus the normal-tangential (Dundurs beta) cross terms between pressure and
  /// traction: normal_of_traction / tangential_of_pressure
  coupled
};

/// Arithmetic of the FFT convolutions. Fields, kernels (built in double) and sparse updates
/// stay double either way; float32 runs the transforms and the spectrum product in single
/// precision (fftwf), which bounds the residual a solver can reach (kFloatFftMinTolerance).
enum class FftPrecision { float64, float32 };

/// Smallest solver tolerance (relative residual) accepted with float32 convolutions. The
/// solvers' residuals stagnate near the convolution's own relative error (~1e-7, measured in
/// docs/performance.md "Float FFTs"); 1e-6 keeps a margin of about ten at every n measured.
inline constexpr double kFloatFftMinTolerance = 1e-6;

/// FFT settings: worker threads, FFTW planner rigour and arithmetic.
struct FftOptions {
  int threads = 1;
  bool measure = false;  ///< FFTW_MEASURE (faster transforms, slower set-up) instead of ESTIMATE
  FftPrecision precision = FftPrecision::float64;
};

/// Distributed over the ranks of a communicator (size > 1), a HalfSpace works on slabs: each
/// rank holds the field rows j in [first_row(), first_row() + local_rows()) as an
/// (nx, local_rows()) Field, and every operator below takes and returns such slabs
/// (docs/mpi-grid.md). Serial, the slab is the whole grid.
class HalfSpace {
 public:
  /// Throws InputError when `comm` is distributed and the options ask for what is not
  /// distributed: float32 transforms, normal-tangential cross terms.
  HalfSpace(const Grid& grid, const Material& material, Coupling coupling, FftOptions fft = {},
            const Communicator& comm = serial_communicator());
  ~HalfSpace();
  HalfSpace(const HalfSpace&) = delete;
  HalfSpace& operator=(const HalfSpace&) = delete;

  const Grid& grid() const { return grid_; }
  const Communicator& communicator() const { return *comm_; }
  /// First grid row (index j) of this rank's slab, and its number of rows.
  int first_row() const { return first_row_; }
  int local_rows() const { return local_rows_; }
  /// A zero slab: (nx, local_rows()).
  Field local_zeros() const { return Field::Zero(grid_.nx, local_rows_); }
  Coupling coupling() const { return coupling_; }
  FftPrecision precision() const { return precision_; }

  /// Smallest relative residual a solver on this operator is allowed to ask for: 0 in double,
  /// kFloatFftMinTolerance in float32 (below it the iterations stagnate on round-off).
  double min_tolerance() const;
  /// Throws InputError naming `solver` when `tolerance` < min_tolerance(): an unreachable
  /// tolerance fails at once instead of iterating to max_iterations on round-off.
  void require_tolerance(double tolerance, const char* solver) const;

  /// Normal displacement u_z = K_z * p (m) of pressure p (Pa).
  void normal(const Field& p, Field& uz);
  /// Tangential displacement of one traction component under the analogy:
  /// u = (E*/G*) K_z * t. Valid for any coupling when only this component is loaded and the
  /// coupling is the analogy; use tangential() for Cerruti.
  void tangential_analogy(const Field& t, Field& u);
  /// Tangential displacements (ux, uy) of tractions (tx, ty) with the selected coupling.
  void tangential(const Field& tx, const Field& ty, Field& ux, Field& uy);

  /// Coupling::coupled with beta != 0: the cross terms are in use. False for every other
  /// coupling and for beta = 0 (identical bodies), where coupled is Cerruti exactly.
  bool cross_coupled() const { return cross_ != 0.0; }
  /// Cross compliance c = beta / (pi E*) (1/Pa) of the material (Material::cross_compliance).
  double cross_compliance() const { return cross_; }
  /// Change of the normal approach of the two surfaces (m) caused by tractions (tx, ty) (Pa)
  /// on body 1: u_z = c sum_j (tx_j Jx + ty_j Jy)(x_i - x_j), Jx, Jy the cell integrals of
  /// x/r^2, y/r^2 (love.hpp). Three transforms. Requires cross_coupled().
  void normal_of_traction(const Field& tx, const Field& ty, Field& uz);
  /// Relative tangential displacement (ux, uy) (m) caused by pressure p (Pa):
  /// u = -c sum_j p_j (Jx, Jy)(x_i - x_j). The transpose of normal_of_traction (reciprocity:
  /// the coupled operator is symmetric). Three transforms. Requires cross_coupled().
  void tangential_of_pressure(const Field& p, Field& ux, Field& uy);

  /// Fourier preconditioner z = K_z^-1 * r: division by the (padded) kernel spectrum, one
  /// convolution's cost (Vollebregt, J. Comput. Phys. 257, 2014; Bazrafshan et al. 2017).
  /// The spectrum is floored at 1e-6 of its largest value; the periodic mean mode (zero in the
  /// spectrum) takes the largest value, so that M stays positive definite.
  void normal_inverse(const Field& r, Field& z);

  /// Adds K_z * e to u for a sparse pressure change e (values at the given linear indices), by
  /// direct summation with the real-space kernel: cheaper than a convolution for few nodes.
  void normal_add_sparse(std::span<const std::int64_t> idx, std::span<const double> val,
                         Field& uz) const;
  /// Same for the analogy tangential operator (scaled normal kernel).
  void tangential_add_sparse(std::span<const std::int64_t> idx, std::span<const double> val,
                             Field& u) const;
  /// tangential_add_sparse on the `targets` nodes only (sorted grid indices; u elsewhere is
  /// left alone): per node and target the same term in the same order, so the same bits there.
  /// Cost per node ~ the targets instead of the grid: a rough contact covers 5-30 % of it.
  void tangential_add_sparse_at(std::span<const std::int64_t> idx, std::span<const double> val,
                                std::span<const std::int64_t> targets, Field& u) const;

  /// Largest number of changed nodes for which the *_add_sparse updates are cheaper than one
  /// convolution: below bench_convolution's measured break-even (76, 88 and 159 nodes at
  /// n = 128, 256 and 512 with the AVX2 summation); 70, 80 and 143 there. 0 on a distributed
  /// grid: a changed node moves every rank's displacements, a convolution's work.
  std::size_t sparse_limit() const;

  /// Normal self-compliance K_z(0,0) (m/Pa): the displacement of a cell under its own unit
  /// pressure; the largest diagonal entry of the operator.
  double normal_self() const { return self_; }
  /// Largest eigenvalue of the normal operator (m/Pa): bound for gradient step sizes.
  double normal_max_eigenvalue() const { return max_eig_; }
  /// E*/G*: ratio of the analogy tangential operator to the normal one.
  double tangential_ratio() const { return ratio_; }

  /// Where a distributed grid's convolutions spend their time (s, this rank, since
  /// construction): moving field rows between the field and transform slabs (MPI_Alltoallv),
  /// and in the FFTW-MPI transforms, which include their global transposes. Zeros when serial.
  struct MpiTimes {
    double moving = 0.0, transforming = 0.0;
  };
  MpiTimes mpi_times() const;
  /// Distributed grid: median wall seconds of one bare global transpose of the spectrum (of
  /// the two a convolution does) over `repeats`; 0 when serial. Collective.
  double mpi_transpose_seconds(int repeats);

  /// Number of forward+inverse convolution passes performed so far (machine-independent cost).
  std::int64_t convolutions() const { return convolutions_; }

 private:
  struct Fft;
  void build_free_kernels(const Material& m);
  void build_periodic_kernels(const Material& m);
  void add_sparse(const Eigen::ArrayXXd& kernel, double scale, std::span<const std::int64_t> idx,
                  std::span<const double> val, Field& u) const;
  void add_sparse_at(const Eigen::ArrayXXd& kernel, double scale, std::span<const std::int64_t> idx,
                     std::span<const double> val, std::span<const std::int64_t> targets,
                     Field& u) const;

  void build_distributed(const Material& m);

  Grid grid_;
  const Communicator* comm_;
  int first_row_ = 0, local_rows_ = 0;
  Coupling coupling_;
  FftPrecision precision_;
  std::unique_ptr<Fft> fft_;
  Eigen::ArrayXXd kz_space_;  ///< normal real-space kernel on the padded grid (m/Pa)
  double self_ = 0.0;
  double max_eig_ = 0.0;
  double ratio_ = 1.0;
  double cross_ = 0.0;  ///< cross compliance c (1/Pa); 0 unless coupled with beta != 0
  std::int64_t convolutions_ = 0;
};

}  // namespace fretbem
