#include "icobrdf/core/support/progress.hpp"

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <memory>
#include <numeric>
#include <thread>

namespace icobrdf {
namespace {

std::ostream*& stream_slot() {
  static std::ostream* out = nullptr;
  return out;
}

double& delay_slot() {
  static double delay = kProgressDelaySeconds;
  return delay;
}

std::string seconds_text(double s) {
  char buf[32];
  if (s < 120) std::snprintf(buf, sizeof buf, "%.0f s", s);
  else if (s < 7200) std::snprintf(buf, sizeof buf, "%.1f min", s / 60);
  else std::snprintf(buf, sizeof buf, "%.1f h", s / 3600);
  return buf;
}

ProgressClock steady_seconds() {
  const auto start = std::chrono::steady_clock::now();
  return [start] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
}

std::vector<double> running_sums(std::vector<double> work) {
  for (double& w : work) w = std::isfinite(w) && w > 0 ? w : 0.0;
  std::partial_sum(work.begin(), work.end(), work.begin());
  return work;
}

// The process's one heartbeat thread: ticks every registered meter each kProgressSampleSeconds, sleeps while
// none is registered, and is joined when the process ends (static destruction). A meter is ticked only while
// registered, and unregistering waits for a round of ticks under way, so no tick reaches a destroyed meter.
class Heartbeat {
 public:
  static Heartbeat& instance() {
    static Heartbeat beat;
    return beat;
  }
  Heartbeat(const Heartbeat&) = delete;
  Heartbeat& operator=(const Heartbeat&) = delete;
  ~Heartbeat() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
  }
  void add(ProgressMeter* m) {
    std::lock_guard<std::mutex> lock(mutex_);
    meters_.push_back(m);
    if (!thread_.joinable()) {
      thread_ = std::thread([this] { run(); });
      ++started_;
    }
    wake_.notify_all();
  }
  void remove(ProgressMeter* m) {
    std::lock_guard<std::mutex> lock(mutex_);
    meters_.erase(std::remove(meters_.begin(), meters_.end(), m), meters_.end());
  }
  long long started() {
    std::lock_guard<std::mutex> lock(mutex_);
    return started_;
  }

 private:
  Heartbeat() = default;
  void run() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stopping_) {
      if (meters_.empty()) {
        wake_.wait(lock, [this] { return stopping_ || !meters_.empty(); });
        continue;
      }
      if (wake_.wait_for(lock, std::chrono::duration<double>(kProgressSampleSeconds), [this] { return stopping_; })) break;
      for (ProgressMeter* m : meters_) m->tick();
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_;
  std::vector<ProgressMeter*> meters_;
  bool stopping_ = false;
  long long started_ = 0;
  std::thread thread_;
};

}  // namespace

void set_progress_stream(std::ostream* out) { stream_slot() = out; }
std::ostream* progress_stream() { return stream_slot(); }
void set_progress_delay(double seconds) { delay_slot() = seconds >= 0 ? seconds : kProgressDelaySeconds; }
double progress_delay() { return delay_slot(); }
long long progress_heartbeat_threads_started() { return Heartbeat::instance().started(); }

std::function<void(const char* stage, double fraction)> stage_progress_lines(const std::string& label) {
  auto last = std::make_shared<double>(-1.0);
  return [label, last, clock = steady_seconds()](const char* stage, double fraction) {
    std::ostream* out = progress_stream();
    const double t = clock();
    if (!out || t < progress_delay() || (*last >= 0.0 && t - *last < kProgressIntervalSeconds)) return;
    *last = t;
    char figures[64];
    std::snprintf(figures, sizeof figures, "%.0f%% after %.0f s", 100.0 * std::clamp(fraction, 0.0, 1.0), t);
    *out << label << ": " << stage << " " << figures << std::endl;
  };
}

ProgressMeter::ProgressMeter(std::string label, long long total_steps)
    : label_(std::move(label)),
      total_(total_steps > 0 ? total_steps : 1),
      clock_(steady_seconds()),
      next_print_(progress_delay()),
      estimate_(static_cast<double>(total_)),
      beating_(progress_stream() != nullptr) {  // nothing to print: not ticked
  if (beating_) Heartbeat::instance().add(this);
}

ProgressMeter::ProgressMeter(std::string label, std::vector<double> step_work)
    : ProgressMeter(std::move(label), std::move(step_work), nullptr) {}

ProgressMeter::ProgressMeter(std::string label, std::vector<double> step_work, ProgressClock clock)
    : label_(std::move(label)),
      total_(step_work.empty() ? 1 : static_cast<long long>(step_work.size())),
      cumulative_(running_sums(std::move(step_work))),
      clock_(clock ? clock : steady_seconds()),
      next_print_(progress_delay()),
      estimate_(cumulative_.empty() || cumulative_.back() <= 0 ? static_cast<double>(total_) : cumulative_.back()) {
  if (!cumulative_.empty() && cumulative_.back() <= 0) cumulative_.clear();  // no work given: count steps
  beating_ = !clock && progress_stream() != nullptr;  // a given clock: the caller ticks
  if (beating_) Heartbeat::instance().add(this);
}

ProgressMeter::~ProgressMeter() {
  if (beating_) Heartbeat::instance().remove(this);
  std::ostream* out = progress_stream();
  if (!printed_ || out == nullptr) return;
  const double elapsed = clock_();
  const bool complete = done_.load() >= total_;
  *out << label_ << ": " << (complete ? "done" : "stopped") << " after " << seconds_text(elapsed) << "\n" << std::flush;
}

double ProgressMeter::work_of(long long steps) const {
  if (cumulative_.empty()) return static_cast<double>(steps);
  if (steps <= 0) return 0;
  return cumulative_[static_cast<size_t>(std::min<long long>(steps, static_cast<long long>(cumulative_.size())) - 1)];
}

void ProgressMeter::step(long long n) {
  const long long done = done_ += n;
  if (progress_stream() == nullptr || done >= total_) return;
  if (clock_() >= next_print_.load()) tick();  // cheap test first; the lock only when a line may be due
}

void ProgressMeter::tick() {
  std::ostream* out = progress_stream();
  if (out == nullptr) return;
  std::lock_guard<std::mutex> lock(mutex_);
  const double elapsed = clock_();
  const long long done = done_.load();
  if (done >= total_) return;  // finished: the destructor says so
  estimate_.record(elapsed, work_of(done));
  const bool line_due = elapsed >= next_print_.load();
  if (elapsed < next_sample_ && !line_due) return;
  next_sample_ = elapsed + kProgressSampleSeconds;
  const std::optional<double> left = estimate_.seconds_left(elapsed);
  if (!line_due) return;
  next_print_.store(elapsed + kProgressIntervalSeconds);
  printed_ = true;
  *out << label_ << ": " << static_cast<int>(std::floor(100 * estimate_.fraction())) << "% after " << seconds_text(elapsed);
  if (left) *out << ", about " << seconds_text(*left) << " left";
  *out << "\n" << std::flush;
}

}  // namespace icobrdf
