#include "fretbem/study/mpi_queue.hpp"

#include <chrono>
#include <cstdlib>
#include <deque>
#include <thread>

#include "../parallel/mpi.hpp"

namespace fretbem {

namespace {

class LocalQueue : public MemberQueue {
 public:
  explicit LocalQueue(std::vector<std::size_t> pending)
      : pending_(pending.begin(), pending.end()) {}
  std::optional<std::size_t> next(bool stopping) override {
    if (stopping || pending_.empty()) return std::nullopt;
    const std::size_t k = pending_.front();
    pending_.pop_front();
    return k;
  }

 protected:
  std::deque<std::size_t> pending_;
};

#ifdef FRETBEM_MPI

constexpr int kTagRequest = 1, kTagReply = 2;
constexpr long kNone = -1;  // reply: no more members for you

// Rank 0: runs members from the list like a serial study and answers the other ranks.
class MasterQueue : public LocalQueue {
 public:
  MasterQueue(std::vector<std::size_t> pending, int size)
      : LocalQueue(std::move(pending)), others_(size - 1) {}

  // A request carries 1 when the asking rank is stopping (it wants no member, only to retire).
  void service(bool stopping) override {
    for (;;) {
      int flag = 0;
      MPI_Status st;
      MPI_Iprobe(MPI_ANY_SOURCE, kTagRequest, MPI_COMM_WORLD, &flag, &st);
      if (!flag) return;
      int asking_to_stop = 0;
      MPI_Recv(&asking_to_stop, 1, MPI_INT, st.MPI_SOURCE, kTagRequest, MPI_COMM_WORLD,
               MPI_STATUS_IGNORE);
      const auto k = next(stopping || asking_to_stop != 0);
      const long reply = k ? long(*k) : kNone;
      MPI_Send(&reply, 1, MPI_LONG, st.MPI_SOURCE, kTagReply, MPI_COMM_WORLD);
      if (!k) ++retired_;
    }
  }
  bool drained() const override { return retired_ == others_; }

 private:
  int others_, retired_ = 0;
};

// Other ranks: one request per free slot; the wait polls so that a signal is still seen.
class WorkerQueue : public MemberQueue {
 public:
  std::optional<std::size_t> next(bool stopping) override {
    if (retired_) return std::nullopt;
    int asking_to_stop = stopping ? 1 : 0;
    MPI_Send(&asking_to_stop, 1, MPI_INT, 0, kTagRequest, MPI_COMM_WORLD);
    long reply = kNone;
    MPI_Request req;
    MPI_Irecv(&reply, 1, MPI_LONG, 0, kTagReply, MPI_COMM_WORLD, &req);
    for (int done = 0; MPI_Test(&req, &done, MPI_STATUS_IGNORE), !done;)
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    if (reply == kNone) retired_ = true;
    return reply == kNone ? std::nullopt : std::optional<std::size_t>(std::size_t(reply));
  }

 private:
  bool retired_ = false;
};

#endif

}  // namespace

std::unique_ptr<MemberQueue> make_local_queue(std::vector<std::size_t> pending) {
  return std::make_unique<LocalQueue>(std::move(pending));
}

#ifdef FRETBEM_MPI

// Open MPI's mpirun, MPICH/Hydra and PMIx launchers (Slurm's srun) set these.
bool mpi_launched() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "PMI_RANK"})
    if (std::getenv(v)) return true;
  return false;
}

MpiSession::MpiSession() {
  MPI_Init(nullptr, nullptr);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiSession::~MpiSession() {
  MPI_Finalize();
}

void MpiSession::barrier() const {
  MPI_Barrier(MPI_COMM_WORLD);
}

std::unique_ptr<MemberQueue> make_mpi_queue(const MpiSession& mpi,
                                            std::vector<std::size_t> pending) {
  if (mpi.rank() == 0) return std::make_unique<MasterQueue>(std::move(pending), mpi.size());
  return std::make_unique<WorkerQueue>();
}

#else

bool mpi_launched() {
  return false;
}
MpiSession::MpiSession() = default;
MpiSession::~MpiSession() = default;
void MpiSession::barrier() const {}
std::unique_ptr<MemberQueue> make_mpi_queue(const MpiSession&, std::vector<std::size_t> pending) {
  return make_local_queue(std::move(pending));
}

#endif

}  // namespace fretbem
