#include "icobrdf/cluster/distributed_projection.hpp"

#include <cstdint>
#include <cstring>
#include <new>

#include "icobrdf/core/support/error.hpp"

namespace icobrdf {
namespace {

// Message tags (distinct from the bank build's, icobrdf/cluster/distributed_bank.cpp). kPartial (r -> 0): a
// rank's share or its failure; kResult (0 -> r): the sum or the failure; kGather (r -> 0): one double.
constexpr int kPartial = 11, kResult = 12, kGather = 13, kRing = 14;

// First byte of kPartial and kResult: the matrices follow, or an error (its kind in the second byte and its
// message after). kResult's error names the failed rank in its message.
enum Status : char { kOk = 0, kFailed = 1 };
enum Kind : char { kInternal = 0, kArgument = 1, kInput = 2, kUnsupported = 3, kIo = 4, kResource = 5 };

Kind kind_of(const std::exception& e) {
  if (dynamic_cast<const ArgumentError*>(&e)) return kArgument;
  if (dynamic_cast<const InputError*>(&e)) return kInput;
  if (dynamic_cast<const UnsupportedError*>(&e)) return kUnsupported;
  if (dynamic_cast<const IoError*>(&e)) return kIo;
  if (dynamic_cast<const ResourceError*>(&e) || dynamic_cast<const std::bad_alloc*>(&e)) return kResource;
  return kInternal;
}

std::exception_ptr error_of_kind(char kind, const std::string& message) {
  switch (kind) {
    case kArgument: return std::make_exception_ptr(ArgumentError(message));
    case kInput: return std::make_exception_ptr(InputError(message));
    case kUnsupported: return std::make_exception_ptr(UnsupportedError(message));
    case kIo: return std::make_exception_ptr(IoError(message));
    case kResource: return std::make_exception_ptr(ResourceError(message));
    default: return std::make_exception_ptr(std::runtime_error(message));
  }
}

std::string on_rank(int rank, int ranks, const std::string& message) {
  return "on rank " + std::to_string(rank) + " of " + std::to_string(ranks) + ": " + message;
}

std::string error_message(Kind kind, const std::string& text) { return std::string{kFailed, static_cast<char>(kind)} + text; }

// Matrices as bytes: count, then per matrix rows, cols (int64) and its doubles (column-major).
std::string matrix_bytes(const std::vector<Eigen::MatrixXd>& m) {
  std::size_t n = 1 + 8;
  for (const auto& x : m) n += 16 + 8 * static_cast<std::size_t>(x.size());
  std::string b(n, '\0');
  b[0] = kOk;
  char* p = b.data() + 1;
  const auto put = [&p](const void* v, std::size_t k) {
    std::memcpy(p, v, k);
    p += k;
  };
  const auto count = static_cast<std::int64_t>(m.size());
  put(&count, 8);
  for (const auto& x : m) {
    const std::int64_t r = x.rows(), c = x.cols();
    put(&r, 8);
    put(&c, 8);
    put(x.data(), 8 * static_cast<std::size_t>(x.size()));
  }
  return b;
}

std::vector<Eigen::MatrixXd> matrices_of(const std::string& b, int rank) {
  const auto bad = [rank] { return InputError("distributed projection: the matrices from rank " + std::to_string(rank) + " are truncated"); };
  std::size_t at = 1;
  const auto get = [&](void* v, std::size_t k) {
    if (at + k > b.size()) throw bad();
    std::memcpy(v, b.data() + at, k);
    at += k;
  };
  std::int64_t count = 0;
  get(&count, 8);
  std::vector<Eigen::MatrixXd> m;
  for (std::int64_t i = 0; i < count; ++i) {
    std::int64_t r = 0, c = 0;
    get(&r, 8);
    get(&c, 8);
    if (r < 0 || c < 0 || static_cast<std::size_t>(r) * static_cast<std::size_t>(c) > (b.size() - at) / 8) throw bad();
    Eigen::MatrixXd x(r, c);
    get(x.data(), 8 * static_cast<std::size_t>(x.size()));
    m.push_back(std::move(x));
  }
  return m;
}

}  // namespace

// The row exchange of a split projection: sums through the projection's exchange, ring steps as kRing
// messages to the previous rank and from the next.
class DistributedProjection::RingExchange : public RowSplitExchange {
 public:
  explicit RingExchange(DistributedProjection& p) : p_(p) {}
  int part() const override { return p_.cluster_.rank(); }
  int parts() const override { return p_.cluster_.size(); }
  void sum(std::vector<Eigen::MatrixXd>& m) override { p_.reduce(m); }
  Eigen::MatrixXd shift(Eigen::MatrixXd block, bool send, bool receive) override {
    Cluster& c = p_.cluster_;
    const int ranks = c.size(), prev = (c.rank() + ranks - 1) % ranks, next = (c.rank() + 1) % ranks;
    if (send) {
      std::vector<Eigen::MatrixXd> v;
      v.push_back(std::move(block));
      std::string bytes = matrix_bytes(v);
      v.clear();  // only the bytes stay alive until delivered
      c.post(prev, kRing, std::move(bytes));
    }
    Eigen::MatrixXd out;
    if (receive) {
      Cluster::Message m = c.wait(next);
      if (m.tag != kRing || m.bytes.empty() || m.bytes[0] != kOk)
        throw std::runtime_error("distributed projection: rank " + std::to_string(next) + " sent no block of P where the ring expected one");
      std::vector<Eigen::MatrixXd> v = matrices_of(m.bytes, next);
      m.bytes.clear();
      m.bytes.shrink_to_fit();
      if (v.size() != 1) throw InputError("distributed projection: rank " + std::to_string(next) + " sent " + std::to_string(v.size()) + " blocks, expected 1");
      out = std::move(v[0]);
    }
    c.finish_sends();
    return out;
  }

 private:
  DistributedProjection& p_;
};

DistributedProjection::DistributedProjection(Cluster& cluster, int projections, bool split_rows)
    : split_rows_(split_rows && cluster.size() > 1), cluster_(cluster), projections_(projections), share_(std::make_shared<StreamingShare>()) {
  share_->part = cluster.rank();
  share_->parts = cluster.size();
  share_->reduce = [this](std::vector<Eigen::MatrixXd>& m) { reduce(m); };
  // An exchange nobody planned: owed from here on like a projection's, so that a rank failing before it joins it.
  share_->sample_sum = [this](std::vector<Eigen::MatrixXd>& m) {
    ++projections_;
    ++sample_sums_;
    reduce(m);
  };
  if (split_rows_) {
    projections_ = 2 + projections;  // the context's sum of G and empty one, then a sum of C per projection
    share_->rows = std::make_shared<RingExchange>(*this);
  }
}

void DistributedProjection::reduce(std::vector<Eigen::MatrixXd>& m) {
  ++exchanges_;
  const int ranks = cluster_.size();
  if (cluster_.rank() != 0) {
    // Posted, not sent: a blocking send of a large message would spin on a core until rank 0, still
    // projecting its own share, takes it (icobrdf/cluster/cluster.hpp).
    cluster_.post(0, kPartial, matrix_bytes(m));
    cluster_.finish_sends();
    const Cluster::Message r = cluster_.wait(0);
    if (r.tag != kResult || r.bytes.empty()) throw std::runtime_error("distributed projection: rank 0 sent an unexpected message");
    if (r.bytes[0] == kFailed) {
      failed_ = true;
      throw RankFailed(r.bytes.substr(2), error_of_kind(r.bytes.size() > 1 ? r.bytes[1] : static_cast<char>(kInternal), r.bytes.substr(2)));
    }
    m = matrices_of(r.bytes, 0);
    return;
  }
  // Rank 0: the shares in rank order; the first failure (lowest rank) wins, but every share is received.
  int failed = -1;
  char kind = kInternal;
  std::string message;
  for (int r = 1; r < ranks; ++r) {
    const Cluster::Message p = cluster_.wait(r);
    if (p.tag != kPartial || p.bytes.empty()) {
      if (failed < 0) failed = r, message = "sent an unexpected message";
      continue;
    }
    if (p.bytes[0] == kFailed) {
      if (failed < 0) failed = r, kind = p.bytes.size() > 1 ? p.bytes[1] : static_cast<char>(kInternal), message = p.bytes.substr(2);
      continue;
    }
    if (failed >= 0) continue;
    try {
      const std::vector<Eigen::MatrixXd> x = matrices_of(p.bytes, r);
      bool same = x.size() == m.size();
      for (std::size_t c = 0; same && c < m.size(); ++c) same = x[c].rows() == m[c].rows() && x[c].cols() == m[c].cols();
      if (!same) throw InputError("distributed projection: rank " + std::to_string(r) + " sent matrices of other sizes than rank 0's");
      for (std::size_t c = 0; c < m.size(); ++c) m[c] += x[c];
    } catch (const std::exception& e) {
      failed = r, kind = kind_of(e), message = e.what();
    }
  }
  if (failed >= 0) {
    failed_ = true;
    const std::string text = on_rank(failed, ranks, message);
    for (int r = 1; r < ranks; ++r) cluster_.post(r, kResult, error_message(static_cast<Kind>(kind), text));
    cluster_.finish_sends();
    throw RankFailed(text, error_of_kind(kind, text));
  }
  // One rank after another, so that rank 0 holds one copy of the sum's bytes at a time.
  const std::string sum = matrix_bytes(m);
  for (int r = 1; r < ranks; ++r) {
    cluster_.post(r, kResult, sum);
    cluster_.finish_sends();
  }
}

bool DistributedProjection::fail(const std::exception& error) noexcept {
  if (failed_ || exchanges_ >= projections_ || in_ring()) return false;
  ++exchanges_;
  failed_ = true;
  try {
    const int ranks = cluster_.size();
    const std::string mine = error_message(kind_of(error), message_line(error.what()));
    if (cluster_.rank() != 0) {
      cluster_.post(0, kPartial, mine);
      cluster_.finish_sends();
      cluster_.wait(0);  // the failure as rank 0 reports it
      return true;
    }
    // Rank 0 failed: receive every share (a sender waits until its message is taken), tell every rank.
    for (int r = 1; r < ranks; ++r) cluster_.wait(r);
    const std::string text = error_message(kind_of(error), on_rank(0, ranks, message_line(error.what())));
    for (int r = 1; r < ranks; ++r) cluster_.post(r, kResult, text);
    cluster_.finish_sends();
  } catch (...) {
    // Nothing more can be done here; mpirun ends the job if a rank is left waiting.
  }
  return true;
}

std::exception_ptr error_on_rank(const std::exception& e, int rank, int ranks) {
  return error_of_kind(kind_of(e), on_rank(rank, ranks, message_line(e.what())));
}

std::vector<double> gather_on_rank0(Cluster& cluster, double value) {
  std::vector<double> out;
  if (cluster.rank() != 0) {
    std::string b(8, '\0');
    std::memcpy(b.data(), &value, 8);
    cluster.send(0, kGather, b);
    return out;
  }
  out.push_back(value);
  for (int r = 1; r < cluster.size(); ++r) {
    const Cluster::Message m = cluster.wait(r);
    double v = 0.0;
    if (m.tag == kGather && m.bytes.size() == 8) std::memcpy(&v, m.bytes.data(), 8);
    out.push_back(v);
  }
  return out;
}

}  // namespace icobrdf
