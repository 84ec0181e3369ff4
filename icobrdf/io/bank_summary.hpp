#pragma once
// A bank's description as `icobrdf bank info` prints it: the file, its format version, creator and
// creation time, its grid (kind, level, cells; null without one), the paths of its operator arrays, and per
// material its name, source, order, symmetry, cosine form, channels, level, grid kind, whether it has a LUT,
// its representation (icobrdf/io/spectrum_file.hpp representation_name), its half-angle lobe when it has one
// (icobrdf/io/half_angle_file.hpp half_angle_summary), and its stored figures and labels.
#include <nlohmann/json.hpp>

#include <string>

#include "icobrdf/io/bank_file.hpp"

namespace icobrdf {

// `bank` as read from `path` (read_bank; the LUTs need not be read).
nlohmann::json bank_summary_json(const BankContents& bank, const std::string& path);

// The same in a few lines: the file's format, creator and date, its grid, the count of operator arrays, and
// one line per material (order, symmetry, channels, source; and its half-angle lobe when it has one).
std::string bank_summary_text(const BankContents& bank, const std::string& path);

}  // namespace icobrdf
