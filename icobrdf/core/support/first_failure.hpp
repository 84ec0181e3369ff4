#pragma once
// The first exception of work spread over OpenMP threads. An exception must not leave an OpenMP region (the
// process would end at once, with no message of ours): a worker's catch calls keep(), the work after it is
// skipped (failed()), and after the region the caller calls rethrow(), which throws that first exception.
// Used by icobrdf/core/support/in_order_sums.hpp (the projections' blocks) and build_lut (icobrdf/core/projection/lut.hpp).
#include <atomic>
#include <exception>
#include <mutex>

namespace icobrdf {

class FirstFailure {
 public:
  // From a catch block: keeps the exception being handled unless an earlier one was kept.
  void keep() noexcept {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!error_) error_ = std::current_exception();
    }
    failed_.store(true, std::memory_order_relaxed);
  }
  bool failed() const { return failed_.load(std::memory_order_relaxed); }
  // After the parallel region: the kept exception, if any.
  void rethrow() const {
    if (error_) std::rethrow_exception(error_);
  }

 private:
  std::mutex mutex_;
  std::exception_ptr error_;
  std::atomic<bool> failed_{false};
};

}  // namespace icobrdf
