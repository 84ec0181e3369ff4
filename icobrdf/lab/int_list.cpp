#include "icobrdf/lab/int_list.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <stdexcept>

#include "icobrdf/core/support/error.hpp"

namespace icobrdf::lab {

std::vector<int> parse_int_list(const std::string& text, int lo, int hi, const std::string& what) {
  std::vector<int> v;
  const auto bad = [&] {
    return ArgumentError(fmt::format("{}: expected 'a..b' or a comma list of integers in [{}, {}], got '{}'", what, lo, hi, text));
  };
  try {
    const auto dots = text.find("..");
    if (dots != std::string::npos) {
      size_t p1 = 0, p2 = 0;
      const int a = std::stoi(text.substr(0, dots), &p1), b = std::stoi(text.substr(dots + 2), &p2);
      if (p1 != dots || p2 != text.size() - dots - 2 || a > b) throw bad();
      for (int k = a; k <= b; ++k) v.push_back(k);
    } else {
      size_t start = 0;
      while (start <= text.size()) {
        const auto comma = text.find(',', start);
        const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        size_t p = 0;
        v.push_back(std::stoi(item, &p));
        if (p != item.size()) throw bad();
        if (comma == std::string::npos) break;
        start = comma + 1;
      }
    }
  } catch (const std::logic_error&) {  // stoi's invalid_argument / out_of_range
    throw bad();
  }
  if (v.empty()) throw bad();
  for (int x : v)
    if (x < lo || x > hi) throw bad();
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

}  // namespace icobrdf::lab
