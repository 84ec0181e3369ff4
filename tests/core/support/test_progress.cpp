// Progress lines of long work (icobrdf/core/support/progress.hpp, progress_estimate.hpp), on a fake clock:
// synthetic sequences of steps whose true remaining time is known, against the lines the meter prints.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <regex>
#include <sstream>
#include <thread>
#include <vector>

#include "icobrdf/core/support/progress.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

// A shown estimate may differ from the true time left by this share (rates measured over whole steps of a
// sequence whose rate is constant or follows the given work) plus the whole second a line rounds to.
constexpr double kLeftRelativeTolerance = 0.15;
constexpr double kLeftRoundingSeconds = 1.0;

struct StreamGuard {
  explicit StreamGuard(std::ostream* s) { set_progress_stream(s); }
  ~StreamGuard() {
    set_progress_stream(nullptr);
    set_progress_delay(kProgressDelaySeconds);
  }
};

struct Line {
  double time;                 // fake seconds when it was printed
  int percent;
  double left = -1;            // -1: no estimate shown
  double true_left = 0;
};

// Runs steps of the given durations (fake seconds) on a meter given `work` per step (empty: equal steps),
// ticking every kProgressSampleSeconds as the heartbeat does, and returns the lines with the true time left.
std::vector<Line> simulate(const std::vector<double>& durations, std::vector<double> work) {
  std::ostringstream out;
  StreamGuard guard(&out);
  double t = 0, total = 0;
  for (double d : durations) total += d;
  if (work.empty()) work.assign(durations.size(), 1.0);
  std::vector<Line> lines;
  {
    ProgressMeter m("work", work, [&t] { return t; });
    double next_tick = kProgressSampleSeconds;
    std::size_t seen = 0;
    auto collect = [&] {
      const std::string s = out.str();
      static const std::regex re("^work: ([0-9]+)% after [0-9.]+ (s|min)(, about ([0-9.]+) (s|min) left)?$");
      std::size_t start = seen;
      for (std::size_t nl = s.find('\n', start); nl != std::string::npos; nl = s.find('\n', start)) {
        const std::string text = s.substr(start, nl - start);
        start = nl + 1;
        std::smatch g;
        ASSERT_TRUE(std::regex_match(text, g, re)) << text;
        Line l{t, std::stoi(g[1]), -1, total - t};
        if (g[3].matched) l.left = std::stod(g[4]) * (g[5] == "min" ? 60 : 1);
        lines.push_back(l);
      }
      seen = start;
    };
    for (double d : durations) {
      const double end = t + d;
      while (next_tick <= end) {
        t = next_tick;
        m.tick();
        collect();
        next_tick += kProgressSampleSeconds;
      }
      t = end;
      m.step();
      collect();
    }
  }
  EXPECT_NE(out.str().find("work: done after"), std::string::npos) << out.str();
  return lines;
}

void expect_honest(const std::vector<Line>& lines, const std::string& what) {
  int shown = 0;
  for (const Line& l : lines) {
    if (l.left < 0) continue;
    ++shown;
    EXPECT_NEAR(l.left, l.true_left, kLeftRelativeTolerance * l.true_left + kLeftRoundingSeconds)
        << what << ": at " << l.time << " s (" << l.percent << "%)";
  }
  EXPECT_GT(shown, 0) << what << ": no estimate was ever shown";
}

TEST(Progress, ShortWorkPrintsNothing) {
  std::ostringstream out;
  StreamGuard guard(&out);
  {
    ProgressMeter m("quick", 100);
    for (int k = 0; k < 100; ++k) m.step();
  }
  EXPECT_EQ(out.str(), "");
}

TEST(Progress, NothingWithoutAStream) {
  set_progress_stream(nullptr);
  double t = 0;
  ProgressMeter m("silent", std::vector<double>(2, 1.0), [&t] { return t; });
  t = kProgressDelaySeconds + 10;
  m.step();
  m.tick();  // would print with a stream
  SUCCEED();
}

TEST(Progress, ConstantRateGivesTheTimeLeftOnceStable) {
  // 60 steps of 1 s: the truth is exact. Nothing before the delay; the first line has no estimate (one
  // sample cannot be stable); lines every kProgressIntervalSeconds.
  const auto lines = simulate(std::vector<double>(60, 1.0), {});
  ASSERT_GE(lines.size(), 10u);
  EXPECT_GE(lines.front().time, kProgressDelaySeconds);
  EXPECT_LT(lines.front().left, 0) << "an estimate from one sample";
  for (std::size_t k = 1; k < lines.size(); ++k) EXPECT_LE(lines[k].time - lines[k - 1].time, kProgressIntervalSeconds + 1e-9);
  expect_honest(lines, "constant rate");
}

TEST(Progress, StepsOfGrowingCostAreCountedByTheirWork) {
  // Step k costs (k + 1) / 20 s, as the reciprocal projection's blocks (a growing prefix of columns): 60
  // steps, 91.5 s. Given their work the estimate is honest; counted as equal steps it says far too little
  // (at a quarter of the steps about a tenth of the work is done), which is what made "about 90 s left"
  // grow to "about 9.5 min left".
  std::vector<double> d, w;
  for (int k = 0; k < 60; ++k) d.push_back((k + 1) / 20.0), w.push_back(k + 1);
  expect_honest(simulate(d, w), "work given");
  const auto counted = simulate(d, {});
  bool too_little = false;
  for (const Line& l : counted) too_little |= l.left >= 0 && l.left < 0.6 * l.true_left;
  EXPECT_TRUE(too_little) << "counting equal steps would be honest here, and this test could not fail";
}

TEST(Progress, AStepLongerThanTheIntervalStillGivesLines) {
  // 10 steps of 1 s, one of 14 s, 10 of 1 s: during the long step the lines go on every
  // kProgressIntervalSeconds with the same percentage, and the time left shown (if any) grows, because the
  // time without a finished step counts in the rate.
  std::vector<double> d(10, 1.0);
  d.push_back(14.0);
  d.insert(d.end(), 10, 1.0);
  const auto lines = simulate(d, {});
  for (std::size_t k = 1; k < lines.size(); ++k) EXPECT_LE(lines[k].time - lines[k - 1].time, kProgressIntervalSeconds + 1e-9);
  double last_left = -1;
  int during = 0;
  for (const Line& l : lines) {
    if (l.time <= 10 || l.time >= 24) continue;
    ++during;
    if (l.left >= 0 && last_left >= 0) {
      EXPECT_GE(l.left, last_left) << "at " << l.time << " s";
    }
    if (l.left >= 0) last_left = l.left;
  }
  EXPECT_GE(during, 2) << "silence during the long step";
}

TEST(Progress, NoEstimateWhileTheRateJumps) {
  // Steps alternating 0.2 s and 6 s: the rate over the recent window swings, so the projected ends disagree
  // by more than kEstimateStableSpread; a shown estimate must still be honest within the rounding of its
  // larger swings (twice the usual tolerance).
  std::vector<double> d;
  for (int k = 0; k < 16; ++k) d.push_back(k % 2 ? 6.0 : 0.2);
  const auto lines = simulate(d, {});
  ASSERT_FALSE(lines.empty());
  EXPECT_LT(lines.front().left, 0);
  for (const Line& l : lines)
    if (l.left >= 0) {
      EXPECT_NEAR(l.left, l.true_left, 2 * kLeftRelativeTolerance * l.true_left + 6.0) << "at " << l.time << " s";
    }
}

TEST(Progress, ASlowerSecondHalfIsFollowed) {
  // 30 steps of 1 s, then 30 of 3 s (the machine got busy): right after the change nothing can know it;
  // once the recent window (half the elapsed time) lies in the slow part, the estimate is honest again.
  std::vector<double> d(30, 1.0);
  d.insert(d.end(), 30, 3.0);
  const auto lines = simulate(d, {});
  int checked = 0;
  for (const Line& l : lines) {
    if (l.time < 2 * 30 || l.left < 0) continue;
    ++checked;
    EXPECT_NEAR(l.left, l.true_left, kLeftRelativeTolerance * l.true_left + 3.0) << "at " << l.time << " s";
  }
  EXPECT_GT(checked, 3);
}

TEST(Progress, EstimateAloneIsExactForAConstantRate) {
  ProgressEstimate e(100);
  for (int s = 1; s <= 40; ++s) e.record(s, 2.0 * s);  // 2 units per second: 80 done at 40 s, 10 s left
  ASSERT_TRUE(e.raw_seconds_left(40).has_value());
  EXPECT_NEAR(*e.raw_seconds_left(40), 10.0, 1e-12);
  // Nothing done after 40 s: by 60 s the recent window (30 s to 60 s) holds 20 units in 30 s, 30 s left.
  EXPECT_NEAR(*e.raw_seconds_left(60), 20.0 / (20.0 / 30.0), 1e-12);
  ProgressEstimate early(100);
  early.record(1, 1);  // 1 % done: below kEstimateMinFraction
  EXPECT_FALSE(early.raw_seconds_left(1).has_value());
}

TEST(Progress, StepsFromManyThreadsAreCounted) {
  std::ostringstream out;
  StreamGuard guard(&out);
  ProgressMeter m("threads", 4000);
  std::vector<std::thread> pool;
  for (int t = 0; t < 4; ++t)
    pool.emplace_back([&] {
      for (int k = 0; k < 1000; ++k) m.step();
    });
  for (auto& t : pool) t.join();
  EXPECT_EQ(out.str(), "");  // under the delay: nothing, and no data race (the sanitizer run checks)
}

TEST(Progress, ShortMetersStartNoThreadOfTheirOwn) {
  // A bank build makes many meters whose work ends before the delay: they share the process's heartbeat
  // thread (started once, by the first meter made while a stream is set) instead of starting one each.
  std::ostringstream out;
  StreamGuard guard(&out);
  for (int k = 0; k < 50; ++k) {
    ProgressMeter m("short", 10);
    for (int s = 0; s < 10; ++s) m.step();
  }
  EXPECT_EQ(progress_heartbeat_threads_started(), 1);
  EXPECT_EQ(out.str(), "");
}

TEST(Progress, TheSharedHeartbeatGivesLinesToEveryMeterDuringALongStep) {
  // Two meters at once, neither taking a step: each gets a line from the heartbeat within a sample period
  // (delay 0), from the one thread. The lines go to a file read back through its own stream (no shared
  // buffer between the threads); polled up to kWaitSeconds (the heartbeat ticks every kProgressSampleSeconds).
  constexpr double kWaitSeconds = 3 * kProgressSampleSeconds;
  const std::string path = testing::TempDir() + "icobrdf_progress_heartbeat.txt";
  std::ofstream out(path, std::ios::trunc);
  StreamGuard guard(&out);
  set_progress_delay(0);
  const auto text = [&] {
    std::ifstream in(path);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  };
  const auto both_printed = [&] {
    const std::string s = text();
    return s.find("first: 0% after") != std::string::npos && s.find("second: 0% after") != std::string::npos;
  };
  {
    ProgressMeter first("first", 2), second("second", 2);
    const auto start = std::chrono::steady_clock::now();
    while (!both_printed() && std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < kWaitSeconds)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    EXPECT_TRUE(both_printed()) << text();
  }
  EXPECT_EQ(progress_heartbeat_threads_started(), 1);
  std::remove(path.c_str());
}

TEST(Progress, StageLinesWaitForTheDelayThenComeAtMostEveryInterval) {
  // Stage lines (a sample fit's stages): none before the delay; with delay 0 the first call prints, the next
  // within kProgressIntervalSeconds does not (both calls are microseconds apart).
  std::ostringstream out;
  StreamGuard guard(&out);
  const auto waiting = stage_progress_lines("fit");  // default delay: 2 s from now
  waiting("solving", 0.5);
  EXPECT_EQ(out.str(), "");
  set_progress_delay(0);
  const auto lines = stage_progress_lines("fit");
  lines("solving", 0.5);
  lines("solving", 1.7);
  EXPECT_EQ(out.str(), "fit: solving 50% after 0 s\n");
}

}  // namespace
}  // namespace icobrdf
