#pragma once
// Wall-clock timing of measurement steps (std::chrono::steady_clock), in seconds.
#include <algorithm>
#include <chrono>
#include <ctime>

namespace icobrdf::lab {

// Seconds of one call of f.
template <class F>
double seconds_of(F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// CPU seconds (all threads of this process, CLOCK_PROCESS_CPUTIME_ID) and wall seconds of one call of f. On
// a machine shared with other work the CPU time leaves out the time the threads waited for a core.
struct CpuWall {
  double cpu = 0.0, wall = 0.0;
};
template <class F>
CpuWall cpu_and_wall_of(F&& f) {
  timespec c0{}, c1{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c0);
  const double wall = seconds_of(f);
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c1);
  return {static_cast<double>(c1.tv_sec - c0.tv_sec) + 1e-9 * static_cast<double>(c1.tv_nsec - c0.tv_nsec), wall};
}

// Best of `repeats` calls of f (the first also pays for first touch and thread start-up).
template <class F>
double best_seconds(int repeats, F&& f) {
  double best = 1e300;
  for (int k = 0; k < repeats; ++k) best = std::min(best, seconds_of(f));
  return best;
}

// One call of f, or the best of up to `repeats` calls when a call takes less than `below` seconds: short
// steps are repeated to see past timer and cache noise.
template <class F>
double seconds_repeating_below(double below, int repeats, F&& f) {
  double best = seconds_of(f);
  if (best < below)
    for (int k = 1; k < repeats; ++k) best = std::min(best, seconds_of(f));
  return best;
}

}  // namespace icobrdf::lab
