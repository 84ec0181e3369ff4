#include "icobrdf/core/support/huge_pages.hpp"

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace icobrdf {

void advise_huge_pages(void* data, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHuge = kHugePageBytes;
  if (data == nullptr || bytes < 2 * kHuge) return;
  const std::uintptr_t begin = (reinterpret_cast<std::uintptr_t>(data) + kHuge - 1) & ~(kHuge - 1);
  const std::uintptr_t end = (reinterpret_cast<std::uintptr_t>(data) + bytes) & ~(kHuge - 1);
  if (end > begin) (void)madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);  // a hint: failure is harmless
#else
  (void)data;
  (void)bytes;
#endif
}

std::size_t huge_page_bytes(const void* data, std::size_t bytes) {
  const auto lo = reinterpret_cast<std::uintptr_t>(data), hi = lo + bytes;
  std::ifstream in("/proc/self/smaps");
  std::string line;
  bool overlaps = false;
  std::size_t total = 0;
  while (std::getline(in, line)) {
    std::uintptr_t begin = 0, end = 0;
    char dash = 0;
    std::istringstream head(line);
    // A mapping's first line: "begin-end perms offset dev inode [path]", hexadecimal addresses.
    if (line.find(':') > line.find(' ') && head >> std::hex >> begin >> dash >> end && dash == '-') {
      overlaps = begin < hi && lo < end;
      continue;
    }
    if (overlaps && line.rfind("AnonHugePages:", 0) == 0) total += std::stoull(line.substr(14)) * 1024;  // "N kB"
  }
  return std::min(total, bytes);
}

Eigen::MatrixXd huge_page_matrix(Eigen::Index rows, Eigen::Index cols) {
  Eigen::MatrixXd m(rows, cols);
  advise_huge_pages(m.data(), sizeof(double) * static_cast<std::size_t>(m.size()));
  return m;
}

}  // namespace icobrdf
