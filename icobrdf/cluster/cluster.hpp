#pragma once
// Cluster: the processes of one `mpirun` job (OpenMPI, MPI_COMM_WORLD) and the few messages icobrdf sends
// between them. This layer (icobrdf/cluster) is built only when CMake finds MPI (option ICOBRDF_MPI); nothing
// below it depends on MPI.
//
// MPI is initialized only by constructing a Cluster, which a program does only when it was started by
// mpirun (started_by_mpirun, icobrdf/cluster/launcher.hpp): a plain run never touches MPI. The thread level asked for is
// MPI_THREAD_SERIALIZED: rank 0 talks to the other ranks from a helper thread while its main thread fits
// (icobrdf/cluster/distributed_bank.hpp), never both at once.
//
// Waiting is by polling (MPI_Iprobe, then a sleep of kPollInterval): OpenMPI's blocking calls spin on a core,
// which would take it from the fitting threads of the same node (mpirun --oversubscribe, OpenMP). The
// destructor waits for every rank the same way (MPI_Ibarrier) before MPI_Finalize.
#include <chrono>
#include <optional>
#include <string>

namespace icobrdf {

// Sleep between two polls of a waiting rank: answers arrive within it, and 5,000 MPI_Iprobe calls a second
// cost far less than the fits they wait for (a cheap material takes tens of milliseconds).
inline constexpr std::chrono::microseconds kPollInterval{200};

class Cluster {
 public:
  // MPI_Init_thread; UnsupportedError when the MPI library cannot give MPI_THREAD_SERIALIZED.
  Cluster();
  ~Cluster();  // every rank reaches it (polling barrier), then MPI_Finalize
  Cluster(const Cluster&) = delete;
  Cluster& operator=(const Cluster&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }

  // Collective: every rank says whether its set-up succeeded; the lowest rank that failed, or -1.
  int first_failed(bool ok);

  struct Message {
    int source = -1;
    int tag = 0;
    std::string bytes;
  };
  // Blocking send of `bytes` (ResourceError above 2 GiB, MPI's count limit).
  void send(int destination, int tag, const std::string& bytes);
  // The next message from `source` (any rank when negative) if one has arrived, else nullopt.
  std::optional<Message> poll(int source = -1);
  // The next message from `source` (any rank when negative), waiting for it by polling.
  Message wait(int source = -1);

 private:
  int rank_ = 0, size_ = 1;
};

}  // namespace icobrdf
