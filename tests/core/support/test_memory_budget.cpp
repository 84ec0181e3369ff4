// Memory available to a request and the parsing of --memory-budget sizes (icobrdf/core/support/memory_budget.hpp).
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/memory_budget.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

TEST(MemoryBudget, ParsesDecimalAndBinaryUnits) {
  EXPECT_EQ(parse_byte_size("512"), 512.0);
  EXPECT_EQ(parse_byte_size("8GB"), 8e9);
  EXPECT_EQ(parse_byte_size("1.5 gb"), 1.5e9);
  EXPECT_EQ(parse_byte_size("2e9"), 2e9);
  EXPECT_EQ(parse_byte_size("8G"), 8.0 * 1024 * 1024 * 1024);    // as ulimit and cgroups read G
  EXPECT_EQ(parse_byte_size("512MiB"), 512.0 * 1024 * 1024);
  EXPECT_EQ(parse_byte_size("3k"), 3.0 * 1024);
}

TEST(MemoryBudget, RefusesSizesThatAreNotSizes) {
  for (const std::string bad : {"", "G", "8Q", "-1G", "0", "nan", "inf", "1e400"}) {
    try {
      parse_byte_size(bad);
      FAIL() << "accepted '" << bad << "'";
    } catch (const ArgumentError& e) {
      EXPECT_NE(std::string(e.what()).find("expected a size"), std::string::npos) << e.what();
    }
  }
}

TEST(MemoryBudget, SizesPrintWithThreeDigits) {
  EXPECT_EQ(byte_size_text(512), "512 B");
  EXPECT_EQ(byte_size_text(1.74e9), "1.74 GB");
  EXPECT_EQ(byte_size_text(13.5e9), "13.5 GB");
  EXPECT_EQ(byte_size_text(238e9), "238 GB");
}

// MemAvailable read here independently of the code under test.
double mem_available_bytes() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  double kb = -1;
  std::string unit;
  while (in >> key >> kb >> unit)
    if (key == "MemAvailable:") return kb * 1024;
  return -1;
}

TEST(MemoryBudget, MeasuredAvailabilityIsAtMostMemAvailable) {
  set_memory_budget(0);
  const double before = mem_available_bytes();
  const auto have = available_memory();
  const double after = mem_available_bytes();
  if (before < 0) GTEST_SKIP() << "no /proc/meminfo";
  EXPECT_GT(have.bytes, 0);
  // Other processes change MemAvailable between the reads; the figure must not exceed the larger one.
  EXPECT_LE(have.bytes, std::max(before, after));
}

TEST(MemoryBudget, BudgetReplacesTheMeasurementAndDecidesRefusal) {
  set_memory_budget(2e9);
  EXPECT_EQ(available_memory().bytes, 2e9);
  EXPECT_EQ(available_memory().source, "memory budget");
  EXPECT_NO_THROW(require_memory(1.9e9, "work", ""));
  try {
    require_memory(3e9, "work", "half of it fits");
    FAIL() << "3 GB accepted under a 2 GB budget";
  } catch (const ResourceError& e) {
    EXPECT_EQ(std::string(e.what()), "work needs about 3.00 GB of memory, 2.00 GB is available (memory budget); half of it fits");
  }
  set_memory_budget(0);
  EXPECT_NE(available_memory().source, "memory budget");
}

// Ranks of one job on one machine share its memory: the measured figure is divided among them (never more
// than the largest MemAvailable read around it, divided), a budget given by the user is not.
TEST(MemoryBudget, SharersDivideTheMeasurementNotTheBudget) {
  set_memory_budget(0);
  set_memory_sharers(4);
  const double before = mem_available_bytes();
  const auto have = available_memory();
  const double after = mem_available_bytes();
  set_memory_budget(2e9);
  const auto budget = available_memory();
  set_memory_budget(0);
  set_memory_sharers(1);
  EXPECT_EQ(budget.bytes, 2e9);
  EXPECT_EQ(budget.source, "memory budget");
  if (before < 0) GTEST_SKIP() << "no /proc/meminfo";
  EXPECT_GT(have.bytes, 0);
  EXPECT_LE(have.bytes, std::max(before, after) / 4);
  EXPECT_NE(have.source.find(" / 4 ranks on this node"), std::string::npos) << have.source;
  EXPECT_EQ(available_memory().source.find("ranks"), std::string::npos) << "1 restores the whole";
}

}  // namespace
}  // namespace icobrdf
