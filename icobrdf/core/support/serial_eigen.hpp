#pragma once
// A guard that runs Eigen's own products on one thread while it lives (the count is restored after the last
// guard ends). Fits that run many small products on several threads at once take one.
#include <Eigen/Core>
#include <omp.h>

#include <mutex>

namespace icobrdf {

// Eigen's products on one thread for the lifetime of the guard (restored after). The fit's products are
// small (nodes x R): threading them gained nothing on an idle 2-core machine and cost 25x on a loaded one
// (measured: GGX 0.2, 64 x 2048 nodes, rank 3: 0.21 s on one thread, 5.6 s on two beside other work).
// Eigen's thread count is one setting for the process, and fits run on several threads at once in a bank
// build (icobrdf/pipeline/bank_builder.hpp): the first guard in sets it, the last one out restores it.
class SerialEigen {
 public:
  SerialEigen() {
    std::lock_guard<std::mutex> g(state().lock);
    if (state().holders++ == 0) {
      // A count equal to this thread's OpenMP one is taken as Eigen's default (follow OpenMP, -1): restoring
      // a pinned count would pin a worker's 1 thread on the whole process after its fit.
      const int n = Eigen::nbThreads();
      state().previous = n == omp_get_max_threads() ? -1 : n;
      Eigen::setNbThreads(1);
    }
  }
  ~SerialEigen() {
    std::lock_guard<std::mutex> g(state().lock);
    if (--state().holders == 0) Eigen::setNbThreads(state().previous);
  }
  SerialEigen(const SerialEigen&) = delete;
  SerialEigen& operator=(const SerialEigen&) = delete;

 private:
  struct State {
    std::mutex lock;
    int holders = 0, previous = 0;
  };
  static State& state() {
    static State s;
    return s;
  }
};

}  // namespace icobrdf
