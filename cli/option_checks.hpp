#pragma once
// Ranges of numeric options as CLI11 validators: an out-of-range value exits 2 with one line naming the
// option, before any work. CLI::Range alone lets nan through, so real-valued options use finite_in.
#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <omp.h>

#include <cmath>
#include <limits>
#include <string>

#include "icobrdf/core/support/error.hpp"

namespace icobrdf::cli {

// A finite number in [lo, hi]; lo_open / hi_open exclude that bound.
inline CLI::Validator finite_in(double lo, double hi, bool lo_open = false, bool hi_open = false) {
  const std::string range = fmt::format("{}{:g}, {:g}{}", lo_open ? "(" : "[", lo, hi, hi_open ? ")" : "]");
  const auto check = [=](std::string& text) {
    double v = 0.0;
    const bool ok = CLI::detail::lexical_cast(text, v) && std::isfinite(v) && (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
    return ok ? std::string() : "expected a finite number in " + range + ", found '" + quoted_text(text) + "'";
  };
  return CLI::Validator(check, "NUMBER in " + range);
}

// Largest finite double: the upper bound of options that only need to be finite.
inline constexpr double kAnyFinite = std::numeric_limits<double>::max();
// A Gram error max|G - I| of 1 or more accepts a basis that is not orthonormal in any sense.
inline CLI::Validator gram_tolerance() { return finite_in(0.0, 1.0, true, true); }

// More threads than this many per processor only queue for the same cores (and a per-thread FP64 peak
// would count cores the machine does not have).
inline constexpr int kThreadsPerProcessor = 4;
inline CLI::Validator thread_count() { return CLI::Range(1, kThreadsPerProcessor * omp_get_num_procs()); }

}  // namespace icobrdf::cli
