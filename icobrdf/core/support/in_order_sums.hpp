#pragma once
// Partial sums of numbered blocks, finished by threads in any order, added to running sums in block order,
// so that the result does not depend on the thread count (the streaming and row-split projections,
// icobrdf/core/projection/streaming_projection.cpp and icobrdf/core/projection/row_split_projection.cpp).
//
// A finished block waits until the blocks before it are added, and whichever thread finishes the next block
// adds every waiting one in order: no thread idles behind a costlier block, as in an OpenMP ordered region
// (blocks that sample only the columns their rows need differ in cost; an ordered region left 15% of
// streaming GGX at level 5, order 8 waiting). A block `ahead` or more past the next to add waits before it
// is kept, which bounds the partial sums alive to `ahead` blocks beside those being computed (one per block
// would be, at level 6, order 40, 1,284 blocks x 861^2 doubles = 7.6 GB).
//
// Failures (icobrdf/core/support/first_failure.hpp): run(block, fn) runs a block's work in a worker and catches its
// exception; the first one is kept, the block counts as added with nothing, and the blocks after it skip
// their work. After the parallel region the caller calls rethrow(), which throws that exception.
#include <Eigen/Core>
#include <condition_variable>
#include <cstddef>
#include <map>
#include <mutex>
#include <utility>
#include <vector>

#include "icobrdf/core/support/first_failure.hpp"
#include "icobrdf/core/support/progress.hpp"

namespace icobrdf {

class InOrderSums {
 public:
  // sums[k] += parts[k] for each block, in block order 0, 1, 2, ...; `progress` (optional) steps once per
  // block added.
  InOrderSums(std::vector<Eigen::MatrixXd>& sums, int ahead, ProgressMeter* progress = nullptr)
      : sums_(sums), ahead_(ahead), progress_(progress) {}
  // Safe from any thread; every block number from 0 up must be added exactly once.
  void add(int block, std::vector<Eigen::MatrixXd>&& parts) {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return block < next_ + ahead_; });
    pending_.emplace(block, std::move(parts));
    for (auto it = pending_.begin(); it != pending_.end() && it->first == next_; it = pending_.erase(it), ++next_) {
      for (std::size_t k = 0; k < it->second.size(); ++k) sums_[k] += it->second[k];
      if (progress_) progress_->step();
    }
    lock.unlock();
    changed_.notify_all();
  }
  // Adds the partial sums fn() returns for `block` (fn runs in a worker thread), or nothing once a block
  // failed; an exception of fn is kept (see above).
  template <class Fn>
  void run(int block, Fn&& fn) noexcept {
    if (!failure_.failed()) {
      try {
        add(block, fn());
        return;
      } catch (...) {
        failure_.keep();
      }
    }
    try {
      add(block, {});  // the block counts as added, with nothing
    } catch (...) {
      // Only the allocation of the empty entry can fail here; nothing more can be done.
    }
  }
  // After the parallel region: the first block's exception, if any.
  void rethrow() const { failure_.rethrow(); }

 private:
  std::vector<Eigen::MatrixXd>& sums_;
  const int ahead_;
  ProgressMeter* progress_;
  std::mutex mutex_;
  std::condition_variable changed_;
  int next_ = 0;
  std::map<int, std::vector<Eigen::MatrixXd>> pending_;
  FirstFailure failure_;
};

}  // namespace icobrdf
