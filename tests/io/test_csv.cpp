// Numeric CSV reader (icobrdf/io/csv.hpp), issue #19: a 50 MB numeric field gave a 50 MB message. Messages quote
// at most kQuoteLimit characters of a field or header and say how long it was.
#include <gtest/gtest.h>

#include <string>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/csv.hpp"
#include "tests/io/io_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

constexpr std::size_t kShortLine = 400;  // path (under /tmp, < 60) + the message's words + one cut quote

std::string error_of(const std::string& path) {
  try {
    read_numeric_csv(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Csv, HugeFieldGivesOneShortLine) {
  test::ScratchDir d;
  const std::string big(1000000, '1');
  for (const std::string& row : {big + "x,2", "nan" + big + ",2", big + "e999999,2"}) {  // not a number, not finite, overflow
    test::write_bytes(d / "a.csv", "a,b\n" + row + "\n");
    const std::string msg = error_of(d / "a.csv");
    ASSERT_FALSE(msg.empty()) << row.substr(0, 10);
    EXPECT_LT(msg.size(), kShortLine) << msg.substr(0, 400);
    EXPECT_NE(msg.find("characters)"), std::string::npos) << msg.substr(0, 400);
  }
}

TEST(Csv, HugeHeaderNameGivesOneShortLine) {
  test::ScratchDir d;
  test::write_bytes(d / "a.csv", "a," + std::string(1000000, 'h') + "\n1,x\n");
  const std::string msg = error_of(d / "a.csv");
  ASSERT_FALSE(msg.empty());
  EXPECT_LT(msg.size(), kShortLine) << msg.substr(0, 400);
}

}  // namespace
}  // namespace icobrdf
