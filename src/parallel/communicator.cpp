#include "fretbem/parallel/communicator.hpp"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "mpi.hpp"

namespace fretbem {

namespace {

class SerialCommunicator final : public Communicator {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  double sum(double x) const override { return x; }
  double max(double x) const override { return x; }
  double min(double x) const override { return x; }
  void sum(std::span<double>) const override {}
  void broadcast(std::span<double>, int) const override {}
  std::vector<double> gather(std::span<const double> v, int) const override {
    return {v.begin(), v.end()};
  }
};

#ifdef FRETBEM_MPI

void finalize_mpi() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized) MPI_Finalize();
}

class MpiCommunicator final : public Communicator {
 public:
  MpiCommunicator() {
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (!initialized) {
      MPI_Init(nullptr, nullptr);
      std::atexit(finalize_mpi);
    }
    comm_ = MPI_COMM_WORLD;
    MPI_Comm_rank(comm_, &rank_);
    MPI_Comm_size(comm_, &size_);
  }
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  double sum(double x) const override { return reduce(x, MPI_SUM); }
  double max(double x) const override { return reduce(x, MPI_MAX); }
  double min(double x) const override { return reduce(x, MPI_MIN); }
  void sum(std::span<double> v) const override {
    MPI_Allreduce(MPI_IN_PLACE, v.data(), int(v.size()), MPI_DOUBLE, MPI_SUM, comm_);
  }
  void broadcast(std::span<double> v, int root) const override {
    MPI_Bcast(v.data(), int(v.size()), MPI_DOUBLE, root, comm_);
  }
  std::vector<double> gather(std::span<const double> v, int root) const override {
    const int mine = int(v.size());
    std::vector<int> counts(size_), offsets(size_, 0);
    MPI_Gather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, root, comm_);
    std::vector<double> all;
    if (rank_ == root) {
      for (int r = 1; r < size_; ++r) offsets[r] = offsets[r - 1] + counts[r - 1];
      all.resize(std::size_t(offsets.back()) + counts.back());
    }
    MPI_Gatherv(v.data(), mine, MPI_DOUBLE, all.data(), counts.data(), offsets.data(), MPI_DOUBLE,
                root, comm_);
    return all;
  }
  const void* native() const override { return &comm_; }

 private:
  double reduce(double x, MPI_Op op) const {
    double out = 0.0;
    MPI_Allreduce(&x, &out, 1, MPI_DOUBLE, op, comm_);
    return out;
  }
  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
};

#endif

}  // namespace

const Communicator& serial_communicator() {
  static const SerialCommunicator serial;
  return serial;
}

#ifdef FRETBEM_MPI

const Communicator& world_communicator() {
  static const MpiCommunicator world;
  return world;
}

#else

const Communicator& world_communicator() {
  throw std::runtime_error(
      "this fretbem was built without MPI (-DFRETBEM_MPI=OFF): no distributed grid");
}

#endif

// Open MPI's mpirun, MPICH/Hydra and PMIx launchers (Slurm's srun) set these.
bool launched_on_several_ranks() {
#ifdef FRETBEM_MPI
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* s = std::getenv(v)) return std::atoi(s) > 1;
#endif
  return false;
}

int launched_rank() {
#ifdef FRETBEM_MPI
  for (const char* v : {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"})
    if (const char* s = std::getenv(v)) return std::atoi(s);
#endif
  return 0;
}

}  // namespace fretbem
