// Progress lines of long work (icobrdf/core/support/progress.hpp).
#include <gtest/gtest.h>

#include <chrono>
#include <regex>
#include <sstream>
#include <thread>

#include "icobrdf/core/support/progress.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

struct StreamGuard {
  explicit StreamGuard(std::ostream* s) { set_progress_stream(s); }
  ~StreamGuard() { set_progress_stream(nullptr); }
};

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
  ProgressMeter m("silent", 2);
  std::this_thread::sleep_for(std::chrono::duration<double>(kProgressDelaySeconds + 0.1));
  m.step();  // would print with a stream
  SUCCEED();
}

TEST(Progress, LongWorkPrintsFractionElapsedAndWhatIsLeft) {
  std::ostringstream out;
  StreamGuard guard(&out);
  {
    ProgressMeter m("sampling", 4);
    std::this_thread::sleep_for(std::chrono::duration<double>(kProgressDelaySeconds + 0.1));
    m.step();  // one of four steps after ~2.1 s: 25%, about 3 x 2.1 = 6.3 s left
    m.step(3);
  }
  const std::string s = out.str();
  EXPECT_TRUE(std::regex_search(s, std::regex("^sampling: 25% after 2 s, about [5-7] s left\n"))) << s;
  EXPECT_TRUE(std::regex_search(s, std::regex("\nsampling: done after 2 s\n$"))) << s;
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

}  // namespace
}  // namespace icobrdf
