#pragma once
// `mpirun -np R icobrdf fit SOURCE ...`: the streaming projection of one material (C = P^T F P, no LUT,
// icobrdf/core/projection/streaming_projection.hpp) spread over R ranks.
//
// Work: rank r projects the blocks of incident rows b with b % R == r (StreamingShare, interleaved: the
// blocks of the reciprocal triangle grow with b, so every rank gets the same mix). Each rank builds the
// grid and the projection operators itself (the same bits on every rank: the same code on the same input)
// and holds them whole; see docs/cluster.md for what that costs.
//
// Reduction (one exchange per projection, deterministic): rank r > 0 sends its channels' M x M matrices to
// rank 0; rank 0 adds them to its own in rank order 0, 1, ..., R-1 and sends the sum to every rank, so that
// all ranks finish the fit with the same matrices (the result is the same bits for a fixed R, and equals one
// process's up to the order of the sums). Bytes moved per projection: 2 (R - 1) x M^2 x channels x 8 plus
// 2 (R - 1) short headers; ranks wait by polling (icobrdf/cluster/cluster.hpp).
//
// Failures: a rank that fails before it has sent its share (set-up, memory estimate, ...) calls fail(),
// which takes its place in the exchange with the error instead of matrices; rank 0 then sends the failure,
// naming the lowest failed rank, to every rank, and every rank throws: rank 0 the error of that rank with
// its kind (ResourceError stays a ResourceError) and "on rank r of R: " before its message, inside a
// RankFailed.
// A rank that dies (signal) makes mpirun end the job and name the rank.
#include <Eigen/Core>

#include <algorithm>
#include <exception>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "icobrdf/cluster/cluster.hpp"
#include "icobrdf/core/projection/streaming_projection.hpp"

namespace icobrdf {

// Thrown by the exchange on every rank when a rank failed: rank 0 reports `error`, the other ranks end with
// a non-zero exit without a message of their own.
struct RankFailed : std::runtime_error {
  RankFailed(const std::string& what, std::exception_ptr e) : std::runtime_error(what), error(std::move(e)) {}
  std::exception_ptr error;  // the failed rank's error, of its kind (ResourceError, ...), as rank 0 reports it
};

// An error of the kind of `e` (icobrdf/core/support/error.hpp; std::runtime_error for others) whose message is
// "on rank RANK of RANKS: " and e's.
std::exception_ptr error_on_rank(const std::exception& e, int rank, int ranks);

class DistributedProjection {
 public:
  // `projections`: how many projections every rank will make (1 for a fit, the repeats of a benchmark); a
  // failure after the last one needs no exchange.
  // `split_rows`: the share carries a row exchange (StreamingShare::rows; icobrdf/core/projection/row_split_projection.hpp):
  // the context (made once, then kept by FitContexts) makes two exchanges (the sum of G, an empty one once
  // every rank has its rows of P), and each projection passes the blocks of P round the ring and then makes
  // one (the sum of C): 2 + projections in all (tag kRing, one matrix per message: C M / R doubles, in pieces
  // of at most 1 GiB when larger, icobrdf/cluster/cluster.hpp).
  DistributedProjection(Cluster& cluster, int projections, bool split_rows = false);
  // This rank's share, for FitRequest::share / FitOptions::share.
  std::shared_ptr<const StreamingShare> share() const { return share_; }
  int exchanges() const { return exchanges_; }
  // Projections whose sum of C was exchanged: a split fit's context makes two exchanges of its own (G and
  // the empty one), also for sources that then project nothing (fits of scattered samples, whose own sums
  // are sample_sums(), not projections).
  int projections_done() const { return (split_rows_ ? std::max(0, exchanges_ - 2) : exchanges_) - sample_sums_; }
  // After `error` on this rank: when a projection's exchange is still owed, take part in it with the error
  // (so that no rank waits for this one) and return true: rank 0 then reports it. False when no exchange
  // was owed (the error came after the last one, or an exchange already carried a failure). Never throws.
  // Also false while the blocks of P go round the ring (in_ring()): the other ranks wait for this one's
  // block there, not in an exchange, so the caller must end the job (Cluster::abort).
  bool fail(const std::exception& error) noexcept;
  // After the context's two exchanges and before the last sum of C of a row-split run: the ranks may be
  // passing blocks of P round the ring (also between two projections, where the next ring may have begun).
  // A sample fit (sample_sums() > 0) runs no ring.
  bool in_ring() const { return split_rows_ && exchanges_ >= 2 && exchanges_ < projections_ && !failed_ && sample_sums_ == 0; }
  // Sums made for a fit of scattered samples (StreamingShare::sample_sum); each also counts as an exchange.
  int sample_sums() const { return sample_sums_; }

 private:
  class RingExchange;
  void reduce(std::vector<Eigen::MatrixXd>& matrices);
  bool split_rows_ = false;
  Cluster& cluster_;
  int projections_ = 1, exchanges_ = 0, sample_sums_ = 0;
  bool failed_ = false;  // an exchange carried a failure: every rank stops, no exchange follows
  std::shared_ptr<StreamingShare> share_;
};

// One number per rank (e.g. its peak resident memory), gathered on rank 0 in rank order (the others get an
// empty vector). Collective: every rank calls it.
std::vector<double> gather_on_rank0(Cluster& cluster, double value);

}  // namespace icobrdf
