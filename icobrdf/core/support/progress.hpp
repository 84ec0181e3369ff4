#pragma once
// Progress of long work, as lines on a stream that the program chooses (std::cerr in the icobrdf program,
// nowhere by default, so library users see nothing unless they ask).
//
//   ProgressMeter m("projecting", total_steps);   // silent until kProgressDelaySeconds have passed
//   m.step();                                     // thread-safe; at most one line per kProgressIntervalSeconds
//
// A line reads "projecting: 35% after 12 s, about 22 s left". The estimate of the time left assumes the
// remaining steps cost what the finished ones did on average; steps of very unequal cost make it rough.
#include <atomic>
#include <chrono>
#include <mutex>
#include <ostream>
#include <string>

namespace icobrdf {

// Work shorter than this prints nothing: a user waits a couple of seconds without wondering.
inline constexpr double kProgressDelaySeconds = 2.0;
// Seconds between two lines: often enough to show movement, rare enough to keep logs short.
inline constexpr double kProgressIntervalSeconds = 5.0;

// Where progress lines go (nullptr: nowhere, the default). Not synchronized with running meters: set it
// before the work starts.
void set_progress_stream(std::ostream* out);
std::ostream* progress_stream();
// Seconds of silence before the first line (default kProgressDelaySeconds; 0 shows progress at once, as
// the program's ICOBRDF_PROGRESS_DELAY does). Set it before the work starts.
void set_progress_delay(double seconds);
double progress_delay();

class ProgressMeter {
 public:
  ProgressMeter(std::string label, long long total_steps);
  ProgressMeter(const ProgressMeter&) = delete;
  ProgressMeter& operator=(const ProgressMeter&) = delete;
  ~ProgressMeter();  // a final "done" line when anything was printed

  void step(long long n = 1);

 private:
  using Clock = std::chrono::steady_clock;
  std::string label_;
  long long total_;
  std::atomic<long long> done_{0};
  Clock::time_point start_;
  std::atomic<double> next_print_;  // seconds since start_ of the next line; written under mutex_
  bool printed_ = false;
  std::mutex mutex_;
};

}  // namespace icobrdf
