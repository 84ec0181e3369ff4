#pragma once
// Comparing banks built from the same scene byte for byte. Two things in a bank depend on the run, not on the
// inputs (docs/file-format.md): the root attribute `created` (fixed by SOURCE_DATE_EPOCH, which the tests
// set) and each material's figure `seconds` (the time its fit took). Each `seconds` value is read with
// `icobrdf bank info --json`, located in the file by its 8 little-endian bytes (exactly one occurrence is
// required) and masked; everything else must be identical, bytes and layout alike.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstring>
#include <string>

#include "tests/cli/cli_runner.hpp"

namespace icobrdf::test {

// The file's bytes with every material's `seconds` figure zeroed; empty with `problem` set on failure.
inline std::string bank_bytes_without_timings(const std::string& path, std::string* problem) {
  const auto info = run_cli({"bank", "info", path, "--json"});
  if (info.exit_code != 0) {
    *problem = path + ": bank info failed: " + info.err;
    return "";
  }
  std::string bytes = slurp(path);
  const nlohmann::json report = nlohmann::json::parse(info.out);
  for (const auto& m : report["materials"]) {
    if (!m.contains("seconds")) continue;
    const double s = m["seconds"].get<double>();
    std::uint64_t u;
    std::memcpy(&u, &s, 8);
    std::string le(8, '\0');
    for (int k = 0; k < 8; ++k) le[static_cast<size_t>(k)] = static_cast<char>(u >> (8 * k));
    const auto at = bytes.find(le);
    if (at == std::string::npos || bytes.find(le, at + 1) != std::string::npos) {
      *problem = path + ": the seconds figure of " + m["name"].get<std::string>() + " is not stored exactly once";
      return "";
    }
    bytes.replace(at, 8, std::string(8, '\0'));
  }
  return bytes;
}

// Several materials on levels 2 and 3 (fits search the level; bank operators at level 3 with P where
// supported); isotropic and anisotropic, pruned and not; float32 or float64 LUTs. A build takes a fraction of
// a second on one thread.
inline std::string identity_scene(bool float32_luts) {
  const std::string luts = float32_luts ? "lut_float32 = true\n" : "lut_float32 = false\n";
  return R"(
[bank]
level = 3
levels = [2, 3]
order_max = 8
store_lut = true
)" + luts + R"(holdout_pairs = 1024

[[material]]
name = "matte"
source = "model:lambert:albedo=0.2"

[[material]]
name = "moon"
source = "model:minnaert:k=2"

[[material]]
name = "clay"
source = "model:oren-nayar:sigma=30,albedo=0.7"
isotropic = false
order = 6
target = 1.0
prune = false

[[material]]
name = "glossy"
source = "model:ggx:alpha=0.6"
target = 0.5
)";
}

inline ::testing::AssertionResult banks_identical(const std::string& a, const std::string& b) {
  std::string problem;
  const std::string x = bank_bytes_without_timings(a, &problem);
  if (!problem.empty()) return ::testing::AssertionFailure() << problem;
  const std::string y = bank_bytes_without_timings(b, &problem);
  if (!problem.empty()) return ::testing::AssertionFailure() << problem;
  if (x.size() != y.size()) return ::testing::AssertionFailure() << a << " has " << x.size() << " bytes, " << b << " " << y.size();
  size_t differ = 0, first = 0;
  for (size_t i = 0; i < x.size(); ++i)
    if (x[i] != y[i] && differ++ == 0) first = i;
  if (differ) return ::testing::AssertionFailure() << a << " and " << b << " differ in " << differ << " bytes from offset " << first;
  return ::testing::AssertionSuccess();
}

}  // namespace icobrdf::test
