#pragma once
// Text for messages as valid UTF-8: the bytes of a message that are not part of a well-formed UTF-8 character
// (RFC 3629: no overlong forms, no surrogates, nothing above U+10FFFF) -- a Latin-1 file name, a character cut
// by a length limit -- written as \xHH, every well-formed character kept. The program's error lines and the
// Python module's exceptions pass through it (printable_text, icobrdf/core/support/error.hpp, has already
// escaped control bytes by then).
#include <cstddef>
#include <cstdio>
#include <string>

namespace icobrdf {

// Length of the well-formed UTF-8 character at s[k] (1 to 4 bytes), or 0 when the bytes there are not one.
inline std::size_t utf8_character_length(const std::string& s, std::size_t k) {
  const auto at = [&s](std::size_t j) { return j < s.size() ? static_cast<unsigned>(static_cast<unsigned char>(s[j])) : 0u; };
  const unsigned b = at(k);
  if (b < 0x80) return 1;
  std::size_t n = 0;
  unsigned lo = 0x80, hi = 0xBF;  // range of the second byte
  if (b >= 0xC2 && b <= 0xDF) {
    n = 2;
  } else if (b >= 0xE0 && b <= 0xEF) {
    n = 3;
    lo = b == 0xE0 ? 0xA0 : 0x80;  // E0 80..9F would be overlong
    hi = b == 0xED ? 0x9F : 0xBF;  // ED A0..BF are surrogates
  } else if (b >= 0xF0 && b <= 0xF4) {
    n = 4;
    lo = b == 0xF0 ? 0x90 : 0x80;  // F0 80..8F would be overlong
    hi = b == 0xF4 ? 0x8F : 0xBF;  // F4 90.. is above U+10FFFF
  } else {
    return 0;
  }
  if (at(k + 1) < lo || at(k + 1) > hi) return 0;
  for (std::size_t j = 2; j < n; ++j)
    if (at(k + j) < 0x80 || at(k + j) > 0xBF) return 0;
  return n;
}

// `s` with every byte outside a well-formed character as \xHH.
inline std::string valid_utf8_text(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t k = 0; k < s.size();) {
    const std::size_t n = utf8_character_length(s, k);
    if (n == 0) {
      char buf[5];
      std::snprintf(buf, sizeof buf, "\\x%02x", static_cast<unsigned>(static_cast<unsigned char>(s[k])));
      out += buf;
      ++k;
    } else {
      out.append(s, k, n);
      k += n;
    }
  }
  return out;
}

}  // namespace icobrdf
