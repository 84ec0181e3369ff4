#pragma once
// Numeric CSV tables with a header row, as icobrdf reads them (direction lists, samples).
//
// Accepted: a UTF-8 byte-order mark at the start (ignored), LF or CRLF line ends, blank lines and lines whose
// first non-blank character is '#' (skipped), surrounding blanks in fields. Refused with an InputError naming
// file:line and expected vs actual: a missing header, a row whose field count differs from the header's, a
// field that is not entirely a decimal number (so a decimal comma "0,5" shows up as a field-count or
// number error), NaN and Inf; a file of more than kMaxCsvBytes (a regular file by its size before reading; a
// device or FIFO once that much is read) or a line of more than kMaxCsvLineBytes (/dev/zero: after 1 MiB).
// Memory: the table takes about kCsvMemoryPerFileByte times the bytes read, held to the memory budget
// (icobrdf/core/support/memory_budget.hpp, ResourceError): before reading for a regular file (from its size),
// every kCsvBudgetStepBytes read for a pipe or a device.
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

// Memory of the table per byte of text: a row of k short numbers ("30,0,40,180,0.1", 16 bytes) is a vector of
// k doubles (40 bytes), its 24-byte header and allocation overhead (16), a line number (4): about 5x; 8 covers
// the reader's own copies.
inline constexpr double kCsvMemoryPerFileByte = 8.0;
inline constexpr std::uint64_t kCsvBudgetStepBytes = std::uint64_t{16} << 20;

CsvTable read_numeric_csv(const std::string& path);

// Throws InputError unless the header begins with exactly these column names (in this order).
void require_columns(const CsvTable& table, const std::vector<std::string>& names);

}  // namespace icobrdf
