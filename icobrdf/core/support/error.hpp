#pragma once
// Error kinds raised by icobrdf. Every message is one line: what went wrong, where, expected vs actual.
// The CLI maps each kind to its own exit code (cli/exit_codes.hpp).
#include <cstddef>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "icobrdf/core/support/build_isa.hpp"  // every program that uses icobrdf checks its CPU once

namespace icobrdf {

// A call's arguments are invalid (m > n, negative order, unknown model name, ...).
struct ArgumentError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};
// The request is valid but exceeds what the numerics support (order beyond what a grid resolves,
// near-singular Gram matrix); the message names the supported limit.
struct UnsupportedError : std::domain_error {
  using std::domain_error::domain_error;
};
// Input data is malformed (file content): the message names the file and the place.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
// The file system refused (cannot create, write, rename, disk full).
struct IoError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The request needs more than the machine offers (memory, by the estimate made before the work starts,
// or an allocation that failed); the message says what it needs, what there is and what would fit.
struct ResourceError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Control bytes (newlines, NUL, ...) of user text or file content as \xHH, so that a message quoting
// them stays one line.
inline std::string printable_text(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) {
      char buf[5];
      std::snprintf(buf, sizeof buf, "\\x%02x", u);
      out += buf;
    } else {
      out += c;
    }
  }
  return out;
}

// Most characters of user text or file content a message quotes: enough to recognise the text and
// spot a typo, few enough that a 7,000-term spec or a 50 MB CSV field still gives one short line.
inline constexpr std::size_t kQuoteLimit = 200;

// `s` ready to quote in a message: printable (above) and, when longer than kQuoteLimit, cut there
// (at a UTF-8 character boundary) with "..." and its full length. Every message quoting input uses it.
inline std::string quoted_text(const std::string& s) {
  if (s.size() <= kQuoteLimit) return printable_text(s);
  std::size_t cut = kQuoteLimit;
  while (cut > 0 && (static_cast<unsigned char>(s[cut]) & 0xC0) == 0x80) --cut;  // not inside a character
  return printable_text(s.substr(0, cut)) + "... (" + std::to_string(s.size()) + " characters)";
}

// Longest message the CLI prints: a backstop for a message that quotes input without quoted_text;
// a few quoted pieces plus paths fit, a runaway message does not.
inline constexpr std::size_t kMessageLimit = 600;

// `what` as one printable line of at most about kMessageLimit characters: head and tail kept (the
// tail usually says what was expected), the middle replaced by the number of characters left out.
inline std::string message_line(const std::string& what) {
  const std::string s = printable_text(what);
  if (s.size() <= kMessageLimit) return s;
  const std::size_t head = kMessageLimit / 2, tail = kMessageLimit / 4;
  return s.substr(0, head) + " ... [" + std::to_string(s.size() - head - tail) + " characters left out] ... " +
         s.substr(s.size() - tail);
}

}  // namespace icobrdf
