// The parsers' text helpers (icobrdf/core/support/text.hpp), against their definitions written out by hand.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "icobrdf/core/support/text.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

using Parts = std::vector<std::string>;

TEST(Text, TrimRemovesWhiteSpaceAtBothEndsOnly) {
  EXPECT_EQ(trim("  a b \t"), "a b");
  EXPECT_EQ(trim("\n\v\f\r x"), "x");  // the six "C" locale white-space bytes
  EXPECT_EQ(trim("x"), "x");
  EXPECT_EQ(trim(" \t "), "");
  EXPECT_EQ(trim(""), "");
  EXPECT_EQ(trim("\xc2\xa0x"), "\xc2\xa0x");  // UTF-8 no-break space: not white space byte by byte
}

TEST(Text, SplitAtKeepsEveryPartBetweenSeparators) {
  EXPECT_EQ(split_at("", ','), Parts({""}));
  EXPECT_EQ(split_at("r", ','), Parts({"r"}));
  EXPECT_EQ(split_at("r,g,b", ','), Parts({"r", "g", "b"}));
  EXPECT_EQ(split_at("a,,b,", ','), Parts({"a", "", "b", ""}));
  EXPECT_EQ(split_at(",", ','), Parts({"", ""}));
  EXPECT_EQ(split_at("8/ a /b", '/'), Parts({"8", " a ", "b"}));  // untrimmed
}

}  // namespace
}  // namespace icobrdf
