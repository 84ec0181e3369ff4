#include "icobrdf/cluster/cluster.hpp"

#include <mpi.h>

#include <climits>
#include <cstdlib>
#include <thread>

#include "icobrdf/cluster/launcher.hpp"
#include "icobrdf/core/error.hpp"

namespace icobrdf {

Cluster::Cluster() {
  // Every rank on this machine (OpenMPI says so before MPI_Init): shared memory is the only transport needed,
  // and OpenMPI's ob1 layer starts in 0.04 s where its default first probes UCX for network devices (0.24 s
  // of MPI_Init here, the start-up of a whole 1,000-material bank build). A user's OMPI_MCA_pml wins.
  if (launcher_world_size() > 1 && launcher_local_size() == launcher_world_size()) ::setenv("OMPI_MCA_pml", "ob1", 0);
  int provided = MPI_THREAD_SINGLE;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  if (provided < MPI_THREAD_SERIALIZED) {
    MPI_Finalize();
    throw UnsupportedError("MPI: the library gives thread level " + std::to_string(provided) +
                           ", expected at least MPI_THREAD_SERIALIZED (" + std::to_string(MPI_THREAD_SERIALIZED) + ")");
  }
}

struct Cluster::Outgoing {
  std::string bytes;
  MPI_Request request = MPI_REQUEST_NULL;
};

Cluster::~Cluster() {
  finish_sends();
  MPI_Request barrier;
  MPI_Ibarrier(MPI_COMM_WORLD, &barrier);
  for (int done = 0;;) {
    MPI_Test(&barrier, &done, MPI_STATUS_IGNORE);
    if (done) break;
    std::this_thread::sleep_for(kPollInterval);
  }
  MPI_Finalize();
}

int Cluster::first_failed(bool ok) {
  const int mine = ok ? size_ : rank_;
  int lowest = size_;
  MPI_Allreduce(&mine, &lowest, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  return lowest < size_ ? lowest : -1;
}

namespace {

void check_count(std::size_t bytes, int destination) {
  if (bytes > static_cast<std::size_t>(INT_MAX))
    throw ResourceError("MPI: a message of " + std::to_string(bytes) + " bytes to rank " + std::to_string(destination) +
                        ", expected at most " + std::to_string(INT_MAX) + " (MPI's count limit)");
}

}  // namespace

void Cluster::send(int destination, int tag, const std::string& bytes) {
  check_count(bytes.size(), destination);
  MPI_Send(bytes.data(), static_cast<int>(bytes.size()), MPI_BYTE, destination, tag, MPI_COMM_WORLD);
}

void Cluster::post(int destination, int tag, std::string bytes) {
  check_count(bytes.size(), destination);
  free_delivered();
  auto o = std::make_unique<Outgoing>();
  o->bytes = std::move(bytes);
  MPI_Isend(o->bytes.data(), static_cast<int>(o->bytes.size()), MPI_BYTE, destination, tag, MPI_COMM_WORLD, &o->request);
  outgoing_.push_back(std::move(o));
}

void Cluster::free_delivered() {
  std::vector<std::unique_ptr<Outgoing>> pending;
  for (auto& o : outgoing_) {
    int done = 0;
    MPI_Test(&o->request, &done, MPI_STATUS_IGNORE);
    if (!done) pending.push_back(std::move(o));
  }
  outgoing_ = std::move(pending);
}

void Cluster::abort(int code) {
  MPI_Abort(MPI_COMM_WORLD, code);
  std::_Exit(code);  // MPI_Abort does not return; this is for the compiler
}

void Cluster::finish_sends() {
  for (free_delivered(); !outgoing_.empty(); free_delivered()) std::this_thread::sleep_for(kPollInterval);
}

std::optional<Cluster::Message> Cluster::poll(int source) {
  int flag = 0;
  MPI_Status status;
  MPI_Iprobe(source < 0 ? MPI_ANY_SOURCE : source, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
  if (!flag) return std::nullopt;
  int count = 0;
  MPI_Get_count(&status, MPI_BYTE, &count);
  Message m;
  m.source = status.MPI_SOURCE;
  m.tag = status.MPI_TAG;
  m.bytes.resize(static_cast<std::size_t>(count));
  MPI_Recv(m.bytes.data(), count, MPI_BYTE, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return m;
}

Cluster::Message Cluster::wait(int source) {
  for (;;) {
    if (auto m = poll(source)) return std::move(*m);
    std::this_thread::sleep_for(kPollInterval);
  }
}

}  // namespace icobrdf
