#pragma once
// The time left of long work, estimated from measured work units (ProgressMeter, icobrdf/core/support/progress.hpp).
//
//   ProgressEstimate e(total_work);
//   e.record(seconds, work_done);        // cumulative work at a time since the start (both non-decreasing)
//   e.seconds_left(now)                  // nullopt until the estimate is stable
//
// The rate is the work done over the recent share kEstimateRecentShare of the elapsed time, up to `now`
// (not up to the last step): a stall or a slower phase lowers it at once, and the time since the last step
// counts as time without work. The time left is (total - done) / rate. An estimate is stable when the
// projected ends (now + left) of the last kEstimateStableSamples samples, at least kEstimateStableSeconds
// apart in all, lie within kEstimateStableSpread of the time left; until then (and at the very start, before
// kEstimateMinFraction of the work is done) there is none. Works whose cost per unit keeps changing (item
// counts of items of unequal cost) are exactly what this cannot fix: the work units must be proportional
// to the cost (ProgressMeter's per-step work).
//
// Accuracy: for work done at a constant rate the estimate is exact up to the step granularity; after a
// change of rate by a factor r it takes about the recent window (half the elapsed time) to follow.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <deque>
#include <optional>
#include <vector>

namespace icobrdf {

// The rate is measured over the last half of the elapsed time: long enough to average uneven steps, short
// enough to follow a slower phase within one half of the time spent.
inline constexpr double kEstimateRecentShare = 0.5;
// No estimate before 3 % of the work: the first steps (allocation, first touches of memory) are not typical.
inline constexpr double kEstimateMinFraction = 0.03;
// Stable: the last 3 projected ends, spanning at least 2 s, agree within 15 % of the time left.
inline constexpr std::size_t kEstimateStableSamples = 3;
inline constexpr double kEstimateStableSeconds = 2.0;
inline constexpr double kEstimateStableSpread = 0.15;

class ProgressEstimate {
 public:
  explicit ProgressEstimate(double total_work) : total_(total_work > 0 ? total_work : 1) {}

  double total() const { return total_; }
  double done() const { return history_.empty() ? 0.0 : history_.back().work; }
  double fraction() const { return std::min(1.0, done() / total_); }

  // Work done by `seconds` (cumulative). Times and work must not decrease; a smaller value is ignored.
  void record(double seconds, double work) {
    if (!history_.empty() && (seconds < history_.back().seconds || work <= history_.back().work)) return;
    if (history_.size() >= kMaxHistory) thin();
    history_.push_back({seconds, work});
  }

  // The seconds left at `now`, or nullopt when the estimate is not stable (see above). Each call is one
  // sample of the stability test: call it at regular times (a meter's ticks), not in a tight loop.
  std::optional<double> seconds_left(double now) {
    const std::optional<double> left = raw_seconds_left(now);
    if (!left) {
      ends_.clear();
      return std::nullopt;
    }
    ends_.push_back({now, now + *left});
    while (ends_.size() > kEstimateStableSamples) ends_.pop_front();
    if (ends_.size() < kEstimateStableSamples || now - ends_.front().seconds < kEstimateStableSeconds) return std::nullopt;
    double lo = ends_.front().work, hi = lo;
    for (const Point& p : ends_) lo = std::min(lo, p.work), hi = std::max(hi, p.work);
    if (hi - lo > kEstimateStableSpread * std::max(*left, 1.0)) return std::nullopt;
    return left;
  }

  // The estimate at `now` without the stability test (nullopt: no work measured in the recent window).
  std::optional<double> raw_seconds_left(double now) const {
    if (fraction() < kEstimateMinFraction || now <= 0) return std::nullopt;
    const double from = now * (1 - kEstimateRecentShare);
    const double rate = (done() - work_at(from)) / (now - from);
    if (!(rate > 0)) return std::nullopt;
    return (total_ - done()) / rate;
  }

 private:
  struct Point {
    double seconds, work;
  };
  static constexpr std::size_t kMaxHistory = 512;  // thinned by half when full: the window needs no more

  // Work done by time t, interpolated linearly between recorded points (0 at time 0).
  double work_at(double t) const {
    Point before{0, 0};
    for (const Point& p : history_) {
      if (p.seconds >= t) {
        if (p.seconds <= before.seconds) return p.work;
        return before.work + (p.work - before.work) * (t - before.seconds) / (p.seconds - before.seconds);
      }
      before = p;
    }
    return before.work;
  }

  void thin() {
    std::vector<Point> kept;
    for (std::size_t k = 0; k < history_.size(); k += 2) kept.push_back(history_[k]);
    kept.back() = history_.back();
    history_.assign(kept.begin(), kept.end());
  }

  double total_;
  std::vector<Point> history_;
  std::deque<Point> ends_;  // (time of the sample, projected end)
};

}  // namespace icobrdf
