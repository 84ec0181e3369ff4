#pragma once
// How the lab's reports spell numbers and tables: scientific and fixed notation, GitHub-markdown tables,
// and JSON numbers (inf and NaN, which JSON cannot hold, become null).
#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <string>
#include <vector>

namespace icobrdf::lab {

// "1.23e-04"; "inf"/"nan" spelled out; exact zero as "0".
inline std::string sci(double x, int digits = 2) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  if (x == 0.0) return "0";
  return fmt::format("{:.{}e}", x, digits);
}
inline std::string fixed(double x, int digits = 3) { return fmt::format("{:.{}f}", x, digits); }

// A GitHub-markdown table (header row, separator, rows), followed by a blank line.
inline std::string md_table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows) {
  std::string s = "|";
  for (const auto& h : header) s += " " + h + " |";
  s += "\n|";
  for (size_t k = 0; k < header.size(); ++k) s += "---|";
  s += "\n";
  for (const auto& r : rows) {
    s += "|";
    for (const auto& c : r) s += " " + c + " |";
    s += "\n";
  }
  return s + "\n";
}

// JSON cannot hold inf/nan: such values become null.
inline nlohmann::json num(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

}  // namespace icobrdf::lab
