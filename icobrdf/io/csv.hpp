#pragma once
// Numeric CSV tables with a header row, as icobrdf reads them (direction lists, samples).
//
// Accepted: a UTF-8 byte-order mark at the start (ignored), LF or CRLF line ends, blank lines and lines whose
// first non-blank character is '#' (skipped), surrounding blanks in fields. Refused with an InputError naming
// file:line and expected vs actual: a missing header, a row whose field count differs from the header's, a
// field that is not entirely a decimal number (so a decimal comma "0,5" shows up as a field-count or
// number error), NaN and Inf; a file of more than kMaxCsvBytes (a regular file by its size before reading; a
// device or FIFO once that much is read) or a line of more than kMaxCsvLineBytes (/dev/zero: after 1 MiB).
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace icobrdf {

struct CsvTable {
  std::string path;
  std::vector<std::string> header;          // trimmed, lower-case column names
  std::vector<std::vector<double>> rows;    // rows x header.size()
  std::vector<int> line_numbers;            // 1-based line of each row in the file
  // The comment lines ('#' first), each as its 1-based line and its text after the '#', trimmed.
  std::vector<std::pair<int, std::string>> comments;
};

// Bounds of what is read: 1 GiB is ~20 million rows of samples; no line of numbers comes near 1 MiB.
inline constexpr std::uint64_t kMaxCsvBytes = std::uint64_t(1) << 30;
inline constexpr std::size_t kMaxCsvLineBytes = std::size_t(1) << 20;

CsvTable read_numeric_csv(const std::string& path);

// Throws InputError unless the header begins with exactly these column names (in this order).
void require_columns(const CsvTable& table, const std::vector<std::string>& names);

}  // namespace icobrdf
