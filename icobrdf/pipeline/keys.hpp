#pragma once
// Texts the bank builder derives from its inputs: resume keys, held-out seeds, progress lines.
#include <cstdint>
#include <cstdio>
#include <string>

#include "icobrdf/core/support/scramble.hpp"

namespace icobrdf {

// x with 17 significant digits (round-trips exactly).
inline std::string exact_decimal(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

// FNV-1a 64-bit hash (icobrdf/core/support/scramble.hpp) as 16 hex digits.
inline std::string fnv1a_hex(const std::string& text) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(fnv1a64(text)));
  return buf;
}

}  // namespace icobrdf
