// icobrdf/lab/child_process.hpp: the child sees the parent's environment minus the removed variables (the parent's
// own is unchanged), its output streams are captured apart, and its exit status or signal is reported.
#include <gtest/gtest.h>
#include <signal.h>

#include <cstdlib>
#include <string>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/lab/child_process.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf::lab {
namespace ICOBRDF_UNITY_ID {

TEST(ChildProcess, RemovesOnlyTheNamedVariablesAndOnlyInTheChild) {
  ASSERT_EQ(::setenv("ICOBRDF_TEST_CHILD_REMOVED", "gone", 1), 0);
  ASSERT_EQ(::setenv("ICOBRDF_TEST_CHILD_REMOVED_NOT", "prefix only", 1), 0);
  ASSERT_EQ(::setenv("ICOBRDF_TEST_CHILD_KEPT", "kept", 1), 0);
  const ChildResult r = run_child({"/usr/bin/env"}, {"ICOBRDF_TEST_CHILD_REMOVED"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.signal, 0);
  EXPECT_EQ(r.out.find("ICOBRDF_TEST_CHILD_REMOVED=gone"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("ICOBRDF_TEST_CHILD_REMOVED_NOT=prefix only\n"), std::string::npos) << "a longer name sharing the prefix is kept";
  EXPECT_NE(r.out.find("ICOBRDF_TEST_CHILD_KEPT=kept\n"), std::string::npos);
  ASSERT_NE(std::getenv("ICOBRDF_TEST_CHILD_REMOVED"), nullptr) << "the parent's environment must not change";
  EXPECT_STREQ(std::getenv("ICOBRDF_TEST_CHILD_REMOVED"), "gone");
}

TEST(ChildProcess, AddedVariablesReplaceTheRemovedOnesOnlyInTheChild) {
  ASSERT_EQ(::setenv("ICOBRDF_TEST_CHILD_SET", "parent", 1), 0);
  const ChildResult r = run_child({"/usr/bin/env"}, {"ICOBRDF_TEST_CHILD_SET"}, {"ICOBRDF_TEST_CHILD_SET=child"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("ICOBRDF_TEST_CHILD_SET=child\n"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("ICOBRDF_TEST_CHILD_SET=parent"), std::string::npos) << "set once, not twice";
  EXPECT_STREQ(std::getenv("ICOBRDF_TEST_CHILD_SET"), "parent") << "the parent's environment must not change";
  // An added name must be removed first (else the child would see it twice), and must be NAME=VALUE.
  EXPECT_THROW(run_child({"/usr/bin/env"}, {}, {"ICOBRDF_TEST_CHILD_SET=child"}), ArgumentError);
  EXPECT_THROW(run_child({"/usr/bin/env"}, {"ICOBRDF_TEST_CHILD_SET"}, {"ICOBRDF_TEST_CHILD_SET"}), ArgumentError);
  EXPECT_THROW(run_child({"/usr/bin/env"}, {"ICOBRDF_TEST_CHILD_SET"}, {"=child"}), ArgumentError);
}

TEST(ChildProcess, CapturesBothStreamsAndTheExitStatus) {
  const ChildResult r = run_child({"/bin/sh", "-c", "echo out; echo err >&2; exit 3"}, {});
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_EQ(r.signal, 0);
  EXPECT_EQ(r.out, "out\n");
  EXPECT_EQ(r.err, "err\n");
}

TEST(ChildProcess, OutputLargerThanAPipeBufferOnBothStreams) {
  // 1 MB on each stream, more than a pipe holds (64 KiB): reading one stream only would deadlock.
  const ChildResult r = run_child({"/bin/sh", "-c", "head -c 1000000 /dev/zero; head -c 1000000 /dev/zero >&2"}, {});
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.out.size(), 1000000u);
  EXPECT_EQ(r.err.size(), 1000000u);
}

TEST(ChildProcess, ReportsTheSignalThatEndedIt) {
  const ChildResult r = run_child({"/bin/sh", "-c", "kill -KILL $$"}, {});
  EXPECT_EQ(r.signal, SIGKILL);
  EXPECT_EQ(r.exit_code, -1);
}

TEST(ChildProcess, AProgramThatCannotStartIsAnIoError) {
  EXPECT_THROW(run_child({"/nonexistent/icobrdf-test-program"}, {}), IoError);
  EXPECT_THROW(run_child({}, {}), ArgumentError);
}

}  // namespace
}  // namespace icobrdf::lab
