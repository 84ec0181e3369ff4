// Message helpers of icobrdf/core/support/error.hpp (issue #19, "messages stay one short line"): quoted_text cuts quoted
// input to kQuoteLimit characters and says how long it was; message_line caps a whole message.
#include <gtest/gtest.h>

#include <string>

#include "icobrdf/core/support/error.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

TEST(QuotedText, ShortTextIsQuotedWhole) {
  const std::string s(kQuoteLimit, 'a');
  EXPECT_EQ(quoted_text(s), s);
  EXPECT_EQ(quoted_text("a\nb"), "a\\x0ab");  // still printable
}

TEST(QuotedText, LongTextIsCutWithItsLength) {
  const std::string s(1000000, '7');
  const std::string q = quoted_text(s);
  EXPECT_EQ(q, std::string(kQuoteLimit, '7') + "... (1000000 characters)");
}

TEST(QuotedText, CutDoesNotSplitAUtf8Character) {
  // kQuoteLimit - 1 ASCII bytes, then 2-byte characters: byte kQuoteLimit is inside the first of them.
  std::string s(kQuoteLimit - 1, 'a');
  for (int k = 0; k < 25; ++k) s += "\xc3\xa9";  // e acute
  const std::string q = quoted_text(s);
  EXPECT_EQ(q.substr(0, q.find("...")), std::string(kQuoteLimit - 1, 'a'));
}

TEST(MessageLine, LongMessageKeepsHeadAndTailWithinTheLimit) {
  // Room for the " ... [N characters left out] ... " marker.
  constexpr std::size_t kMarkerRoom = 60;
  const std::string what = "head: " + std::string(50000000, 'x') + " expected THE END";
  const std::string line = message_line(what);
  EXPECT_LE(line.size(), kMessageLimit + kMarkerRoom);
  EXPECT_EQ(line.rfind("head: ", 0), 0u) << line.substr(0, 80);
  EXPECT_NE(line.find("expected THE END"), std::string::npos);
  EXPECT_EQ(message_line("short\nmessage"), "short\\x0amessage");
}

}  // namespace
}  // namespace icobrdf
