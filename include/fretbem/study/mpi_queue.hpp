// Sweeps over MPI ranks (built with -DFRETBEM_MPI=ON): dynamic load balancing by
// request. Rank 0 keeps the list of pending members and runs members itself; every other rank
// asks rank 0 for one member index whenever it has a free slot, so a rank that drew cheap
// members simply asks more often. Results travel through the members' status files (a shared
// file system, as on any cluster), and rank 0 writes sweep.csv after a barrier.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "fretbem/study/member_pool.hpp"

namespace fretbem {

/// True when this binary was built with MPI and the process was started by an MPI launcher
/// (mpirun, mpiexec, srun with PMI/PMIx): then `fretbem sweep` initialises MPI. A plain
/// serial start never touches MPI.
bool mpi_launched();

/// MPI_Init on construction, MPI_Finalize on destruction; size 1 and rank 0 without MPI.
class MpiSession {
 public:
  MpiSession();
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }
  /// Every rank reaches this point (before rank 0 writes the aggregate).
  void barrier() const;

 private:
  int rank_ = 0, size_ = 1;
};

/// The queue of this rank: rank 0 serves `pending` (and runs from it), others ask rank 0.
std::unique_ptr<MemberQueue> make_mpi_queue(const MpiSession& mpi,
                                            std::vector<std::size_t> pending);

/// The serial queue: the given members in order.
std::unique_ptr<MemberQueue> make_local_queue(std::vector<std::size_t> pending);

}  // namespace fretbem
