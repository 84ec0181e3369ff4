// The free-space check before large temporary files (icobrdf/io/disk_space.hpp): a request no disk holds is
// refused with one line (what, where, needed vs free), a tiny one passes, an unknown folder is left to the
// write that follows.
#include <gtest/gtest.h>

#include <regex>
#include <string>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/disk_space.hpp"
#include "tests/support/unity_id.hpp"

using namespace icobrdf;

namespace ICOBRDF_UNITY_ID {

// More bytes than any file system offers (an exabyte).
constexpr double kNoDiskHolds = 1e18;

TEST(DiskSpace, TheTemporaryFolderReportsFreeSpace) {
  EXPECT_GT(free_disk_bytes(testing::TempDir()), 0.0);
  EXPECT_LT(free_disk_bytes("/no-such-folder/anywhere"), 0.0);
}

TEST(DiskSpace, ARequestNoDiskHoldsIsRefusedWithOneLine) {
  const std::string folder = testing::TempDir();
  try {
    require_disk_space(kNoDiskHolds, folder, "spooling", "choose another folder");
    FAIL() << "an exabyte was accepted";
  } catch (const ResourceError& e) {
    const std::string m = e.what();
    EXPECT_TRUE(std::regex_match(m, std::regex("spooling needs about 1000 PB of disk space in .+, [0-9.]+ [kMGTP]?B is free "
                                               "there \\(statvfs\\); choose another folder")))
        << m;
    EXPECT_NE(m.find(folder), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

TEST(DiskSpace, ATinyRequestOrAnUnknownFolderPasses) {
  EXPECT_NO_THROW(require_disk_space(1.0, testing::TempDir(), "a byte", ""));
  EXPECT_NO_THROW(require_disk_space(kNoDiskHolds, "/no-such-folder/anywhere", "left to the write", ""));
}

}  // namespace ICOBRDF_UNITY_ID
