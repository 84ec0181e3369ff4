#pragma once
// Progress of long work, as lines on a stream that the program chooses (std::cerr in the icobrdf program,
// nowhere by default, so library users see nothing unless they ask).
//
//   ProgressMeter m("projecting", total_steps);   // silent until kProgressDelaySeconds have passed
//   m.step();                                     // thread-safe
//
// A line reads "projecting: 35% after 12 s, about 22 s left", or "projecting: 35% after 12 s" while the
// time left is not known well enough (icobrdf/core/support/progress_estimate.hpp: the rate of the recent
// half of the elapsed time, shown once three samples agree within 15 %). Steps of unequal cost are given
// their work (the second constructor), so the fraction and the rate count work, not steps; those steps
// must then be taken in order (the first n steps done are steps 0..n-1, as InOrderSums takes them).
// While work goes on a line comes every kProgressIntervalSeconds even when no step finishes (a heartbeat
// thread ticks every meter of the process each kProgressSampleSeconds), so a long step is never silence.
// That thread is one per process, shared by all meters: started by the first meter made while a stream is
// set, it then sleeps without a meter and lives until the process ends, so that a bank build's many short
// meters start no thread each.
#include <atomic>
#include <chrono>
#include <functional>
#include <mutex>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "icobrdf/core/support/progress_estimate.hpp"

namespace icobrdf {

// Work shorter than this prints nothing: a user waits a couple of seconds without wondering.
inline constexpr double kProgressDelaySeconds = 2.0;
// Seconds between two lines: often enough to show movement, rare enough to keep logs short.
inline constexpr double kProgressIntervalSeconds = 5.0;
// Seconds between two samples of the estimate (the heartbeat's period): three samples settle it in 2 s.
inline constexpr double kProgressSampleSeconds = 1.0;

// Where progress lines go (nullptr: nowhere, the default). Not synchronized with running meters: set it
// before the work starts.
void set_progress_stream(std::ostream* out);
std::ostream* progress_stream();
// Seconds of silence before the first line (default kProgressDelaySeconds; 0 shows progress at once, as
// the program's ICOBRDF_PROGRESS_DELAY does). Set it before the work starts.
void set_progress_delay(double seconds);
double progress_delay();
// Heartbeat threads started in this process so far: 0 until a meter is made with a stream set, then 1.
long long progress_heartbeat_threads_started();

// Seconds since the meter started; a test passes a fake one (no heartbeat thread then: it calls tick()).
using ProgressClock = std::function<double()>;

// Lines of work that knows its stage and the fraction of it done, not its steps (a sample fit's stages,
// icobrdf/core/fit/fit_progress.hpp): "<label>: <stage> 35% after 12 s", on progress_stream(), once
// progress_delay() has passed since this call and then at most every kProgressIntervalSeconds (whole
// seconds, however long); no estimate of the time left. Call it from one thread.
std::function<void(const char* stage, double fraction)> stage_progress_lines(const std::string& label);

class ProgressMeter {
 public:
  // total_steps steps of equal cost.
  ProgressMeter(std::string label, long long total_steps);
  // One step per entry of step_work (its cost in any unit, >= 0), taken in order.
  ProgressMeter(std::string label, std::vector<double> step_work);
  // Either, with a given clock and no heartbeat (the caller ticks).
  ProgressMeter(std::string label, std::vector<double> step_work, ProgressClock clock);
  ProgressMeter(const ProgressMeter&) = delete;
  ProgressMeter& operator=(const ProgressMeter&) = delete;
  ~ProgressMeter();  // a final "done" line when anything was printed

  void step(long long n = 1);
  // Samples the estimate and prints a line when one is due (the heartbeat calls it every
  // kProgressSampleSeconds; step() calls it when a line may be due).
  void tick();

 private:
  double work_of(long long steps) const;  // the work of the first `steps` steps

  std::string label_;
  long long total_;
  std::vector<double> cumulative_;  // work of the first k + 1 steps (empty: equal steps)
  ProgressClock clock_;
  std::atomic<long long> done_{0};
  std::atomic<double> next_print_;  // seconds since the start of the next line; written under mutex_
  double next_sample_ = 0;          // under mutex_
  bool printed_ = false;
  ProgressEstimate estimate_;
  std::mutex mutex_;
  bool beating_ = false;  // ticked by the process's heartbeat thread
};

}  // namespace icobrdf
