#pragma once
// A source that remembers its values: eval() of the same batch of pairs (the same rows, bit for bit) gives
// the values computed the first time, without evaluating the source again. The lobe fits of one material ask
// for the same node batches many times (a grid of the ladder, then the hybrid's rounds and ranks on that
// grid, each over the source minus a body; the peak-sampled check at the same pairs each time), which for a
// source slow to evaluate (BrdfSource::slow_to_evaluate: an RGL file's inverse warp per pair) is most of a
// material's time.
// Batches are keyed by two independent 64-bit hashes of their rows' bit patterns (and their row count); the
// values of at most `max_bytes` of batches are kept, the oldest dropped first. Everything else is the
// wrapped source's. Thread-safe (eval may be called from several threads).
// Constructed with ReciprocalPart, it remembers (and answers with) the source's reciprocal part
// f_rec(a, b) = (f(a, b) + f(b, a)) / 2 instead of f: what a reciprocal representation can hold of a
// non-reciprocal measurement. The bank fits that for a material judged against the reciprocal part, so that a
// lobe fitted at one ordering of each node pair does not take the data's asymmetry at that ordering as error
// (fit() is the source's: a projection onto the reciprocal modes is the same for f and f_rec).
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <utility>

#include "icobrdf/io/brdf_source.hpp"

namespace icobrdf {

// Values kept per material: the largest lobe grid of the ladder (512 x 128 x 64 node pairs of 3 channels,
// 100 MB) and the batches around it fit; two materials fitted at once stay well within a few hundred MB.
inline constexpr std::size_t kMemoSourceBytes = std::size_t{160} << 20;

class MemoSource final : public BrdfSource {
 public:
  explicit MemoSource(const BrdfSource& source, std::size_t max_bytes = kMemoSourceBytes) : source_(source), max_bytes_(max_bytes) {}
  struct ReciprocalPart {};
  MemoSource(const BrdfSource& source, ReciprocalPart) : source_(source), max_bytes_(kMemoSourceBytes), reciprocal_part_(true) {}
  std::string spec() const override { return source_.spec(); }
  int channels() const override { return source_.channels(); }
  std::vector<std::string> channel_names() const override { return source_.channel_names(); }
  Eigen::MatrixXd eval(const RowMatrix3d& wi, const RowMatrix3d& wr) const override;
  bool has_delta() const override { return source_.has_delta(); }
  std::vector<std::string> notes() const override { return source_.notes(); }
  Spectrum fit(const ProjectionContext& ctx, const FitOptions& options) const override { return source_.fit(ctx, options); }
  bool values_only_at_samples() const override { return source_.values_only_at_samples(); }
  bool may_miss_values() const override { return source_.may_miss_values(); }
  bool isotropic_by_construction() const override { return source_.isotropic_by_construction(); }
  bool reciprocal_by_construction() const override { return source_.reciprocal_by_construction(); }
  bool judged_at_own_samples() const override { return source_.judged_at_own_samples(); }
  bool slow_to_evaluate() const override { return source_.slow_to_evaluate(); }
  int largest_sample_order(bool isotropic) const override { return source_.largest_sample_order(isotropic); }
  std::optional<HalfAngleNodes> own_half_angle_nodes() const override { return source_.own_half_angle_nodes(); }
  std::optional<OwnHeldOut> own_held_out(const HeldOutRequest& request) const override { return source_.own_held_out(request); }

  // Batches answered from memory and evaluated, for reports and tests.
  long long hits() const;
  long long misses() const;

 private:
  using Key = std::pair<std::uint64_t, std::uint64_t>;
  const BrdfSource& source_;
  std::size_t max_bytes_;
  bool reciprocal_part_ = false;
  mutable std::mutex lock_;
  mutable std::map<Key, Eigen::MatrixXd> values_;
  mutable std::deque<Key> order_;  // oldest first
  mutable std::size_t bytes_ = 0;
  mutable long long hits_ = 0, misses_ = 0;
};

}  // namespace icobrdf
