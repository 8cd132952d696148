#include "fretbem/elastic/half_space.hpp"

#include <algorithm>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <type_traits>
#include <variant>

#include "fretbem/core/errors.hpp"
#include "half_space_fft.hpp"

namespace fretbem {

using fft_detail::make_spectrum;
using fft_detail::spectrum_scale;

HalfSpace::HalfSpace(const Grid& grid, const Material& material, Coupling coupling, FftOptions fft,
                     const Communicator& comm)
    : grid_(grid),
      comm_(&comm),
      local_rows_(grid.ny),
      coupling_(coupling),
      precision_(fft.precision) {
  if (grid.nx < 1 || grid.ny < 1 || !(grid.h > 0))
    throw std::invalid_argument("HalfSpace: empty grid");
  if (comm.distributed()) {
    build_distributed(material);
    return;
  }
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

// The slab-decomposed operator (mpi_engine.hpp): double transforms, the analogy and Cerruti
// kernels of free and periodic grids.
void HalfSpace::build_distributed(const Material& m) {
  if (precision_ != FftPrecision::float64)
    throw InputError(
        "solver.fft_precision = float is not available on a distributed grid (mpirun -n K > 1): "
        "use double");
  ratio_ = m.E_star() / m.G_star();
  if (coupling_ == Coupling::coupled && m.cross_compliance() != 0.0)
    throw InputError(
        "solver.coupling = coupled with dissimilar bodies (normal-tangential cross terms) is not "
        "available on a distributed grid (mpirun -n K > 1): use cerruti or one process");
  const kernel_values::Constants c(grid_, m, coupling_ != Coupling::analogy, 0.0);
  fft_ = std::make_unique<Fft>();
  fft_->mpi = std::make_unique<fft_detail::MpiEngine>(*comm_, grid_, c);
  const auto rows = fft_->mpi->field_rows();
  first_row_ = rows.first, local_rows_ = rows.count;
  self_ = fft_->mpi->self();
  max_eig_ = fft_->mpi->max_eigenvalue();
}

HalfSpace::~HalfSpace() = default;

HalfSpace::MpiTimes HalfSpace::mpi_times() const {
  if (!fft_->mpi) return {};
  return {fft_->mpi->seconds_moving, fft_->mpi->seconds_transforming};
}

double HalfSpace::mpi_transpose_seconds(int repeats) {
  return fft_->mpi ? fft_->mpi->transpose_seconds(repeats) : 0.0;
}

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

}  // namespace fretbem
