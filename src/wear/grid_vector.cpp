// Grid vectors of the ODE wear integrators: SUNDIALS' serial vector on one process; on a grid
// distributed over MPI ranks its MPI+X vector over a serial vector of this rank's slab.
//
// ARKODE's step decisions (weighted RMS error norms) and SPGMR's dot products are vector
// reductions inside SUNDIALS. The MPI+X vector does each as the serial vector's local
// operation plus one MPI_Allreduce, for every reduction SUNDIALS has (norms, dot products,
// minima, fused and "local" variants), so every rank takes the same step decisions; a serial
// vector with hand-overridden reduction operations would be wrong, silently, in any operation
// left out. One process keeps the serial vector and its speed.
#include "fretbem/core/errors.hpp"
#include "ode_data.hpp"

#ifdef FRETBEM_MPI
#include "../parallel/mpi.hpp"
// mpi.hpp first: SUNDIALS' MPI headers include <mpi.h> without skipping the C++ bindings.
#include <nvector/nvector_mpiplusx.h>
#endif

namespace fretbem::wear_detail {

namespace {

void destroy_serial(N_Vector v) {
  N_VDestroy(v);
}

#ifdef FRETBEM_MPI
// N_VMake_MPIPlusX does not own the local vector it wraps.
void destroy_mpi_plus_x(N_Vector v) {
  N_Vector local = N_VGetLocalVector_MPIPlusX(v);
  N_VDestroy(v);
  N_VDestroy(local);
}
#endif

}  // namespace

Eigen::Map<Field> slab(const OdeData& d, N_Vector v) {
  const HalfSpace& hs = *d.model.half_space;
  return Eigen::Map<Field>(N_VGetArrayPointer(v), hs.grid().nx, hs.local_rows());
}

GridVector new_grid_vector(const HalfSpace& hs, SUNContext ctx) {
  const sunindextype local = sunindextype(hs.grid().nx) * hs.local_rows();
  N_Vector y = N_VNew_Serial(local, ctx);
  if (!y) throw SolverError("SUNDIALS: no vector");
  const Communicator& comm = hs.communicator();
  if (!comm.distributed()) return GridVector(y, destroy_serial);
#ifdef FRETBEM_MPI
  N_Vector all = N_VMake_MPIPlusX(*static_cast<const MPI_Comm*>(comm.native()), y, ctx);
  if (!all) {
    N_VDestroy(y);
    throw SolverError("SUNDIALS: no MPI+X vector");
  }
  return GridVector(all, destroy_mpi_plus_x);
#else
  N_VDestroy(y);
  throw SolverError("a distributed grid in a build without MPI");
#endif
}

}  // namespace fretbem::wear_detail
