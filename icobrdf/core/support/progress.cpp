#include "icobrdf/core/support/progress.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

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

}  // namespace

void set_progress_stream(std::ostream* out) { stream_slot() = out; }
std::ostream* progress_stream() { return stream_slot(); }
void set_progress_delay(double seconds) { delay_slot() = seconds >= 0 ? seconds : kProgressDelaySeconds; }
double progress_delay() { return delay_slot(); }

ProgressMeter::ProgressMeter(std::string label, long long total_steps)
    : label_(std::move(label)),
      total_(total_steps > 0 ? total_steps : 1),
      clock_(steady_seconds()),
      next_print_(progress_delay()),
      estimate_(static_cast<double>(total_)) {
  start_heartbeat();
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
  if (!clock) start_heartbeat();
}

void ProgressMeter::start_heartbeat() {
  if (progress_stream() == nullptr) return;  // nothing to print: no thread
  heartbeat_ = std::thread([this] {
    std::unique_lock<std::mutex> lock(stop_mutex_);
    while (!stop_wait_.wait_for(lock, std::chrono::duration<double>(kProgressSampleSeconds), [this] { return stopping_; })) {
      lock.unlock();
      tick();
      lock.lock();
    }
  });
}

ProgressMeter::~ProgressMeter() {
  if (heartbeat_.joinable()) {
    {
      std::lock_guard<std::mutex> lock(stop_mutex_);
      stopping_ = true;
    }
    stop_wait_.notify_all();
    heartbeat_.join();
  }
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
