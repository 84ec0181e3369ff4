#pragma once
// Cluster: the processes of one `mpirun` job (OpenMPI, MPI_COMM_WORLD) and the few messages icobrdf sends
// between them. This layer (icobrdf/cluster) is built only when CMake finds MPI (option ICOBRDF_MPI); nothing
// below it depends on MPI.
//
// MPI is initialized only by constructing a Cluster, which a program does only when it was started by
// mpirun (started_by_mpirun, icobrdf/cluster/launcher.hpp): a plain run never touches MPI. When every rank runs
// on one machine (OpenMPI's OMPI_COMM_WORLD_LOCAL_SIZE equals the world size) and OMPI_MCA_pml is unset,
// the constructor sets it to ob1 (shared memory) before MPI_Init: OpenMPI's default probes UCX first, which
// took 0.24 s of a 2-rank start-up against 0.04 s (benchmarks/RESULTS.md, "MPI bank build"). The thread level asked for is
// MPI_THREAD_SERIALIZED: rank 0 talks to the other ranks from a helper thread while its main thread fits
// (icobrdf/cluster/distributed_bank.hpp), never both at once.
//
// Messages of any size. MPI counts in int, so a message of more than kMessagePieceBytes goes as a header
// (its tag and size, on the reserved tag kPieceTag) followed by its pieces of at most kMessagePieceBytes,
// on the same tag; MPI keeps messages from one rank on one tag in order, so poll() takes the header and then
// the pieces and returns the message whole, under its own tag. ICOBRDF_MPI_PIECE_BYTES (a positive byte
// count, read at start-up) sets a smaller piece: for tests, and for MPI libraries with a lower limit.
//
// Waiting is by polling (MPI_Iprobe, then a sleep of kPollInterval): OpenMPI's blocking calls spin on a core,
// which would take it from the fitting threads of the same node (mpirun --oversubscribe, OpenMP). The
// destructor waits for every rank the same way (MPI_Ibarrier) before MPI_Finalize.
#include <chrono>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace icobrdf {

// Sleep between two polls of a waiting rank. Rank 0's helper polls all through a build, so this is its CPU
// cost: 200 us cost 0.3-0.6 s of CPU per 1,000 cheap materials (benchmarks/RESULTS.md, "MPI bank build"),
// 1 ms about a fifth of that. The latency it adds is hidden: every rank holds materials ahead, enough for
// 20 ms of its fitting (icobrdf/cluster/distributed_bank.cpp).
inline constexpr std::chrono::microseconds kPollInterval{1000};

// 1 GiB: under MPI's int count (2 GiB - 1) with room to spare, and large enough that the header and the
// per-piece overhead are nothing against the copy of a piece.
inline constexpr std::size_t kMessagePieceBytes = std::size_t{1} << 30;
// Reserved for the headers and pieces of large messages; no icobrdf message uses it.
inline constexpr int kPieceTag = 30000;

class Cluster {
 public:
  // MPI_Init_thread; UnsupportedError when the MPI library cannot give MPI_THREAD_SERIALIZED.
  Cluster();
  ~Cluster();  // finish_sends(); every rank reaches it (polling barrier); MPI_Finalize
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
  // Blocking send of `bytes` (of any size: pieces above the piece size, as described above).
  void send(int destination, int tag, const std::string& bytes);
  // Non-blocking send: returns at once, the bytes are kept until delivered (a large message waits for its
  // receiver; the sender fits meanwhile). finish_sends() waits, polling, until every one was delivered.
  void post(int destination, int tag, std::string bytes);
  void finish_sends();
  // Ends every rank of the job now (MPI_Abort with `code`): for a failure where the other ranks wait for
  // this one in a way no message can release.
  [[noreturn]] void abort(int code);
  // The next message from `source` (any rank when negative) if one has arrived, else nullopt.
  std::optional<Message> poll(int source = -1);
  // The next message from `source` (any rank when negative), waiting for it by polling.
  Message wait(int source = -1);

 private:
  struct Outgoing;
  // Completed posts are freed by the next post or finish_sends.
  void free_delivered();
  int rank_ = 0, size_ = 1;
  std::size_t piece_bytes_ = kMessagePieceBytes;  // ICOBRDF_MPI_PIECE_BYTES when set
  std::vector<std::unique_ptr<Outgoing>> outgoing_;
};

}  // namespace icobrdf
