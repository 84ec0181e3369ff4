// record_stop_signals (icobrdf/io/program_end.hpp): after it, SIGINT and SIGTERM only set the flag the work
// polls (a command that stops cleanly on its own, as bank build), and the process goes on.
#include <gtest/gtest.h>

#include <csignal>

#include "icobrdf/io/program_end.hpp"
#include "tests/support/unity_id.hpp"

using namespace icobrdf;

namespace ICOBRDF_UNITY_ID {

TEST(ProgramEnd, RecordedStopSignalsSetTheFlagAndTheProcessGoesOn) {
  std::atomic<int>& stop = record_stop_signals();
  stop.store(0);
  ASSERT_EQ(std::raise(SIGTERM), 0);
  EXPECT_EQ(stop.load(), SIGTERM);
  ASSERT_EQ(std::raise(SIGINT), 0);
  EXPECT_EQ(stop.load(), SIGINT);
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
}

}  // namespace ICOBRDF_UNITY_ID
