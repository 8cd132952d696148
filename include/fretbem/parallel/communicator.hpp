// Communicator: the one reduction layer of a grid distributed over processes. Every global
// quantity a solver forms from its nodes (dot products, norms, total force, rigid shift,
// extrema, "any node") is the local value passed through it, so that a solver's code is the
// same on one process and on K MPI ranks. The serial communicator returns its argument: the
// serial arithmetic, and so its results, are unchanged bit for bit.
#pragma once

#include <span>
#include <vector>

namespace fretbem {

class Communicator {
 public:
  virtual ~Communicator() = default;
  /// This process's rank, 0..size()-1; the rank that writes files is 0.
  virtual int rank() const = 0;
  virtual int size() const = 0;
  bool distributed() const { return size() > 1; }

  /// Sum, largest and smallest value of x over the ranks, on every rank.
  virtual double sum(double x) const = 0;
  virtual double max(double x) const = 0;
  virtual double min(double x) const = 0;
  /// Element-wise sums of a small vector over the ranks, in place, on every rank (one message
  /// for several scalars of one iteration).
  virtual void sum(std::span<double> v) const = 0;
  /// True on every rank when it is true on one.
  bool any(bool x) const { return max(x ? 1.0 : 0.0) > 0.0; }
  /// Rank root's v copied into v on every rank (same size everywhere).
  virtual void broadcast(std::span<double> v, int root) const = 0;
  /// The ranks' v concatenated in rank order on rank root (empty elsewhere): what a one-rank
  /// writer needs of a distributed field.
  virtual std::vector<double> gather(std::span<const double> v, int root) const = 0;

  /// The MPI communicator (a pointer to an MPI_Comm) for FFTW-MPI; null when serial.
  virtual const void* native() const { return nullptr; }
};

/// The communicator of one process: size 1, every reduction the identity.
const Communicator& serial_communicator();

/// MPI_COMM_WORLD (MPI initialised on first use and finalised at exit when nobody else did).
/// Throws std::runtime_error in a build without MPI (-DFRETBEM_MPI=OFF).
const Communicator& world_communicator();

/// True when this binary was built with MPI and started by an MPI launcher with more than
/// one rank (mpirun -n K, K > 1; srun): the environment says so before MPI is initialised.
bool launched_on_several_ranks();
/// This process's rank as its launcher gave it (0 when not launched by MPI), known before MPI
/// is initialised: which rank of a refused start prints the one error line.
int launched_rank();

}  // namespace fretbem
