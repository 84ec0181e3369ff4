// Messages as valid UTF-8 (icobrdf/io/utf8_text.hpp): bytes outside well-formed characters (RFC 3629) are
// escaped, characters of every length kept; and the program's error line for a path with a Latin-1 byte.
#include <gtest/gtest.h>

#include <string>

#include "icobrdf/io/utf8_text.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

TEST(Utf8Text, BytesOutsideWellFormedCharactersAreEscaped) {
  EXPECT_EQ(valid_utf8_text("caf\xe9.csv"), "caf\\xe9.csv");                          // Latin-1 e acute
  EXPECT_EQ(valid_utf8_text("caf\xc3\xa9.csv"), "caf\xc3\xa9.csv");                   // UTF-8 e acute kept
  EXPECT_EQ(valid_utf8_text("a\xc3"), "a\\xc3");                                     // cut short at the end
  EXPECT_EQ(valid_utf8_text("\xc3" "a"), "\\xc3" "a");                                // lead byte without continuation
  EXPECT_EQ(valid_utf8_text("\xc0\xaf"), "\\xc0\\xaf");                              // overlong '/'
  EXPECT_EQ(valid_utf8_text("\xe0\x80\xaf"), "\\xe0\\x80\\xaf");                     // overlong, 3 bytes
  EXPECT_EQ(valid_utf8_text("\xed\xa0\x80"), "\\xed\\xa0\\x80");                     // a surrogate
  EXPECT_EQ(valid_utf8_text("\xe2\x82\xac"), "\xe2\x82\xac");                        // the euro sign kept
  EXPECT_EQ(valid_utf8_text("\xf0\x9f\x98\x80"), "\xf0\x9f\x98\x80");                // U+1F600 kept
  EXPECT_EQ(valid_utf8_text("\xf4\x90\x80\x80"), "\\xf4\\x90\\x80\\x80");            // above U+10FFFF
  EXPECT_EQ(valid_utf8_text("\xff\xfe"), "\\xff\\xfe");
  EXPECT_EQ(valid_utf8_text("plain ASCII, \\x0a kept"), "plain ASCII, \\x0a kept");
}

}  // namespace ICOBRDF_UNITY_ID
}  // namespace icobrdf
