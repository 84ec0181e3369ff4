// advise_huge_pages and the LUTs the library allocates (icobrdf/core/support/huge_pages.hpp). The kernel says per
// mapping, in /proc/self/smaps, whether transparent huge pages may back it ("THPeligible"). With the system
// setting "madvise" (Debian's default, and this project's CI machines) only advised mappings are eligible, so
// the tests expect the advised buffer and build_lut's LUT eligible and a plain buffer not; with "always"
// every mapping is eligible and only the first half can be checked; with "never", or off Linux, nothing can
// be, and the tests say so and skip.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>

#include "icobrdf/core/support/huge_pages.hpp"
#include "icobrdf/core/projection/lut.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/grid/reference_grids.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

constexpr std::uintptr_t kHugePage = kHugePageBytes;

// The bracketed word of /sys/kernel/mm/transparent_hugepage/enabled ("always", "madvise" or "never"), or ""
// where the file does not exist.
std::string thp_mode() {
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto open = all.find('['), close = all.find(']');
  return open == std::string::npos || close == std::string::npos ? "" : all.substr(open + 1, close - open - 1);
}

// The number after `field` (e.g. "THPeligible:", "AnonHugePages:") in the mapping of /proc/self/smaps that
// holds `address`; -1 when not found.
long long smaps_field(const void* address, const std::string& field) {
  const auto a = reinterpret_cast<std::uintptr_t>(address);
  std::ifstream in("/proc/self/smaps");
  std::string line;
  bool inside = false;
  while (std::getline(in, line)) {
    std::uintptr_t lo = 0, hi = 0;
    char dash = 0;
    std::istringstream head(line);
    if (head >> std::hex >> lo >> dash >> hi && dash == '-' && line.find(':') > line.find(' ')) {
      inside = lo <= a && a < hi;
      continue;
    }
    if (inside && line.rfind(field, 0) == 0) return std::stoll(line.substr(field.size()));
  }
  return -1;
}

int thp_eligible(const void* address) { return static_cast<int>(smaps_field(address, "THPeligible:")); }

// The first 2 MiB boundary inside a buffer.
const void* first_huge_boundary(const double* data) {
  return reinterpret_cast<const void*>((reinterpret_cast<std::uintptr_t>(data) + kHugePage - 1) & ~(kHugePage - 1));
}

bool checkable(const std::string& mode) { return mode == "madvise" || mode == "always"; }

TEST(HugePages, AnAdvisedBufferIsEligibleAndAPlainOneIsNotUnderMadvise) {
  const std::string mode = thp_mode();
  if (!checkable(mode)) GTEST_SKIP() << "transparent huge pages are '" << mode << "' here: no mapping can be eligible";
  // 16 MiB each: several whole huge pages inside, far above the 4 MiB below which the advice is skipped.
  Eigen::MatrixXd advised = huge_page_matrix(2048, 1024);
  const Eigen::MatrixXd plain(2048, 1024);
  EXPECT_EQ(thp_eligible(first_huge_boundary(advised.data())), 1);
  if (mode == "always") GTEST_SKIP() << "with THP 'always' every mapping is eligible: the plain buffer cannot be told apart";
  EXPECT_EQ(thp_eligible(first_huge_boundary(plain.data())), 0);
}

TEST(HugePages, HugePageBytesIsWhatTheKernelReportsOfTheRange) {
  const std::string mode = thp_mode();
  if (mode != "madvise") GTEST_SKIP() << "transparent huge pages are '" << mode << "' here, not 'madvise': a plain buffer may have them too";
  constexpr std::size_t kBytes = sizeof(double) * 2048 * 1024;
  Eigen::MatrixXd advised = huge_page_matrix(2048, 1024), plain(2048, 1024);
  advised.setConstant(1.0);  // written: the kernel backs the advised part now, with huge pages where it finds them
  plain.setConstant(1.0);
  EXPECT_EQ(huge_page_bytes(plain.data(), kBytes), 0u) << "a buffer never advised has no huge page under 'madvise'";
  const std::size_t h = huge_page_bytes(advised.data(), kBytes);
  EXPECT_LE(h, kBytes);
  EXPECT_EQ(h % kHugePage, 0u) << "huge pages are whole 2 MiB pages";
  // The advised interior is a mapping of its own (madvise splits it off): its AnonHugePages is all of them.
  EXPECT_EQ(static_cast<long long>(h), 1024 * smaps_field(first_huge_boundary(advised.data()), "AnonHugePages:"));
}

TEST(HugePages, BuildLutAdvisesItsMatrices) {
  const std::string mode = thp_mode();
  if (mode != "madvise") GTEST_SKIP() << "transparent huge pages are '" << mode << "' here, not 'madvise': the advice cannot be observed";
  const Grid g = build_lat_long_grid(30, 60, 1);  // 1800 cells: a 26 MB LUT
  const Lut lut = build_lut(*parse_model("lambert"), g, false);
  ASSERT_EQ(lut.channels.size(), 1u);
  ASSERT_EQ(lut.cells(), 1800);
  EXPECT_EQ(thp_eligible(first_huge_boundary(lut.channels[0].data())), 1);
}

}  // namespace ICOBRDF_UNITY_ID
}  // namespace icobrdf
