#include "icobrdf/cluster/cluster.hpp"

#include <mpi.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <thread>

#include "icobrdf/cluster/launcher.hpp"
#include "icobrdf/core/support/error.hpp"

namespace icobrdf {

namespace {

// ICOBRDF_MPI_PIECE_BYTES, or kMessagePieceBytes when unset.
std::size_t piece_bytes_from_environment() {
  const char* v = std::getenv("ICOBRDF_MPI_PIECE_BYTES");
  if (!v) return kMessagePieceBytes;
  char* end = nullptr;
  errno = 0;
  const long long n = std::strtoll(v, &end, 10);
  if (errno != 0 || end == v || *end != '\0' || n < 1 || n > INT_MAX)
    throw ArgumentError(std::string("ICOBRDF_MPI_PIECE_BYTES: '") + v + "', expected a byte count from 1 to " + std::to_string(INT_MAX));
  return static_cast<std::size_t>(n);
}

}  // namespace

Cluster::Cluster() {
  piece_bytes_ = piece_bytes_from_environment();  // before MPI starts: a refusal leaves no MPI to finish
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
  std::string header;                 // a large message's tag and size (two int64), else empty
  std::vector<MPI_Request> requests;  // one, or the header's and one per piece
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

void Cluster::send(int destination, int tag, const std::string& bytes) {
  if (tag == kPieceTag) throw std::logic_error("Cluster::send: tag " + std::to_string(tag) + " is reserved for message pieces");
  if (bytes.size() > piece_bytes_) {
    post(destination, tag, bytes);
    finish_sends();
    return;
  }
  MPI_Send(bytes.data(), static_cast<int>(bytes.size()), MPI_BYTE, destination, tag, MPI_COMM_WORLD);
}

void Cluster::post(int destination, int tag, std::string bytes) {
  if (tag == kPieceTag) throw std::logic_error("Cluster::post: tag " + std::to_string(tag) + " is reserved for message pieces");
  free_delivered();
  auto o = std::make_unique<Outgoing>();
  o->bytes = std::move(bytes);
  const std::size_t size = o->bytes.size();
  if (size <= piece_bytes_) {
    o->requests.emplace_back();
    MPI_Isend(o->bytes.data(), static_cast<int>(size), MPI_BYTE, destination, tag, MPI_COMM_WORLD, &o->requests.back());
  } else {
    const std::int64_t head[2] = {tag, static_cast<std::int64_t>(size)};
    o->header.assign(reinterpret_cast<const char*>(head), sizeof head);
    o->requests.reserve(1 + (size + piece_bytes_ - 1) / piece_bytes_);
    o->requests.emplace_back();
    MPI_Isend(o->header.data(), static_cast<int>(o->header.size()), MPI_BYTE, destination, kPieceTag, MPI_COMM_WORLD, &o->requests.back());
    for (std::size_t at = 0; at < size; at += piece_bytes_) {
      o->requests.emplace_back();
      MPI_Isend(o->bytes.data() + at, static_cast<int>(std::min(piece_bytes_, size - at)), MPI_BYTE, destination, kPieceTag, MPI_COMM_WORLD,
                &o->requests.back());
    }
  }
  outgoing_.push_back(std::move(o));
}

void Cluster::free_delivered() {
  std::vector<std::unique_ptr<Outgoing>> pending;
  for (auto& o : outgoing_) {
    int done = 0;
    MPI_Testall(static_cast<int>(o->requests.size()), o->requests.data(), &done, MPI_STATUSES_IGNORE);
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
  if (m.tag != kPieceTag) {
    m.bytes.resize(static_cast<std::size_t>(count));
    MPI_Recv(m.bytes.data(), count, MPI_BYTE, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    return m;
  }
  // A large message: its header, then its pieces, which the sender posted right after it.
  const auto bad = [&m](const std::string& what) {
    return InputError("MPI: a large message from rank " + std::to_string(m.source) + ": " + what);
  };
  std::int64_t head[2] = {0, -1};
  if (count != static_cast<int>(sizeof head)) throw bad("a header of " + std::to_string(count) + " bytes, expected " + std::to_string(sizeof head));
  MPI_Recv(head, count, MPI_BYTE, m.source, kPieceTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  if (head[0] < 0 || head[0] == kPieceTag || head[0] > INT_MAX || head[1] < 0)
    throw bad("header with tag " + std::to_string(head[0]) + " and size " + std::to_string(head[1]));
  m.tag = static_cast<int>(head[0]);
  m.bytes.resize(static_cast<std::size_t>(head[1]));
  for (std::size_t at = 0; at < m.bytes.size();) {
    MPI_Status piece;
    MPI_Probe(m.source, kPieceTag, MPI_COMM_WORLD, &piece);
    int n = 0;
    MPI_Get_count(&piece, MPI_BYTE, &n);
    if (n <= 0 || static_cast<std::size_t>(n) > m.bytes.size() - at)
      throw bad("a piece of " + std::to_string(n) + " bytes where " + std::to_string(m.bytes.size() - at) + " remained");
    MPI_Recv(m.bytes.data() + at, n, MPI_BYTE, m.source, kPieceTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    at += static_cast<std::size_t>(n);
  }
  return m;
}

Cluster::Message Cluster::wait(int source) {
  for (;;) {
    if (auto m = poll(source)) return std::move(*m);
    std::this_thread::sleep_for(kPollInterval);
  }
}

}  // namespace icobrdf
