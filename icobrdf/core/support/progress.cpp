#include "icobrdf/core/support/progress.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

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

}  // namespace

void set_progress_stream(std::ostream* out) { stream_slot() = out; }
std::ostream* progress_stream() { return stream_slot(); }
void set_progress_delay(double seconds) { delay_slot() = seconds >= 0 ? seconds : kProgressDelaySeconds; }
double progress_delay() { return delay_slot(); }

ProgressMeter::ProgressMeter(std::string label, long long total_steps)
    : label_(std::move(label)), total_(total_steps > 0 ? total_steps : 1), start_(Clock::now()), next_print_(progress_delay()) {}

ProgressMeter::~ProgressMeter() {
  std::ostream* out = progress_stream();
  if (!printed_ || out == nullptr) return;
  const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
  const bool complete = done_.load() >= total_;
  *out << label_ << ": " << (complete ? "done" : "stopped") << " after " << seconds_text(elapsed) << "\n" << std::flush;
}

void ProgressMeter::step(long long n) {
  const long long done = done_ += n;
  std::ostream* out = progress_stream();
  if (out == nullptr) return;
  const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
  if (elapsed < next_print_ || done >= total_) return;  // cheap test first; the lock only when a line may be due
  std::lock_guard<std::mutex> lock(mutex_);
  if (elapsed < next_print_) return;
  next_print_.store(elapsed + kProgressIntervalSeconds);
  printed_ = true;
  const double fraction = static_cast<double>(done) / static_cast<double>(total_);
  const double left = elapsed * (1 - fraction) / std::max(fraction, 1e-9);
  *out << label_ << ": " << static_cast<int>(std::floor(100 * fraction)) << "% after " << seconds_text(elapsed) << ", about "
       << seconds_text(left) << " left\n"
       << std::flush;
}

}  // namespace icobrdf
