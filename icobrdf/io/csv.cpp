#include "icobrdf/io/csv.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <sys/stat.h>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/memory_budget.hpp"
#include "icobrdf/core/support/text.hpp"

namespace icobrdf {
namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::string field;
  std::istringstream ss(line);
  while (std::getline(ss, field, ',')) out.push_back(trim(field));
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

std::string where(const std::string& path, int line) { return path + ":" + std::to_string(line); }

// std::getline with the bounds of csv.hpp: InputError once a line passes kMaxCsvLineBytes or the bytes read
// pass kMaxCsvBytes (`total` counts them), so that a device or a FIFO without end is refused early.
bool bounded_getline(std::istream& in, std::string& line, const std::string& path, int lineno, std::uint64_t& total) {
  line.clear();
  std::streambuf* buf = in.rdbuf();
  bool any = false;
  for (int c = buf->sbumpc(); c != std::char_traits<char>::eof(); c = buf->sbumpc()) {
    any = true;
    if (++total > kMaxCsvBytes)
      throw InputError(path + ": more than " + std::to_string(kMaxCsvBytes >> 20) + " MiB, the largest CSV file read");
    if (c == '\n') return true;
    if (line.size() >= kMaxCsvLineBytes)
      throw InputError(where(path, lineno) + ": a line longer than " + std::to_string(kMaxCsvLineBytes >> 10) +
                       " KiB (not a CSV file of numbers?)");
    line.push_back(static_cast<char>(c));
  }
  return any;
}

void hold_csv_to_budget(const std::string& path, double text_bytes, const char* when) {
  require_memory(kCsvMemoryPerFileByte * text_bytes, "reading " + path + " (" + byte_size_text(text_bytes) + " of CSV " + when + ")",
                 "a smaller file needs less");
}

}  // namespace

CsvTable read_numeric_csv(const std::string& path) {
  struct stat st{};
  const bool regular = ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
  if (regular && static_cast<std::uint64_t>(st.st_size) > kMaxCsvBytes)
    throw InputError(path + ": " + std::to_string(static_cast<std::uint64_t>(st.st_size) >> 20) + " MiB, more than the " +
                     std::to_string(kMaxCsvBytes >> 20) + " MiB of the largest CSV file read");
  if (regular) hold_csv_to_budget(path, static_cast<double>(st.st_size), "text");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open for reading");
  CsvTable t;
  t.path = path;
  std::string line;
  int lineno = 0;
  std::uint64_t total = 0, next_check = kCsvBudgetStepBytes;
  while (bounded_getline(in, line, path, lineno + 1, total)) {
    ++lineno;
    if (!regular && total >= next_check) {
      hold_csv_to_budget(path, static_cast<double>(total), "read so far");
      next_check += kCsvBudgetStepBytes;
    }
    if (lineno == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string content = trim(line);
    if (content.empty()) continue;
    if (content[0] == '#') {
      t.comments.emplace_back(lineno, trim(content.substr(1)));
      continue;
    }
    auto fields = split(content);
    if (t.header.empty()) {
      for (auto& f : fields) {
        std::transform(f.begin(), f.end(), f.begin(), [](unsigned char c) { return std::tolower(c); });
        if (f.empty()) throw InputError(where(path, lineno) + ": empty column name in header");
      }
      t.header = std::move(fields);
      continue;
    }
    if (fields.size() != t.header.size())
      throw InputError(where(path, lineno) + ": expected " + std::to_string(t.header.size()) + " fields, found " +
                       std::to_string(fields.size()));
    std::vector<double> row(fields.size());
    for (size_t k = 0; k < fields.size(); ++k) {
      const std::string& f = fields[k];
      char* end = nullptr;
      errno = 0;
      const double v = f.empty() ? 0.0 : std::strtod(f.c_str(), &end);
      if (f.empty() || end != f.c_str() + f.size() || errno == ERANGE)
        throw InputError(where(path, lineno) + ": column '" + quoted_text(t.header[k]) +
                         "' expected a number, found '" + quoted_text(f) + "'");
      if (!std::isfinite(v))
        throw InputError(where(path, lineno) + ": column '" + quoted_text(t.header[k]) +
                         "' expected a finite number, found '" + quoted_text(f) + "'");
      row[k] = v;
    }
    t.rows.push_back(std::move(row));
    t.line_numbers.push_back(lineno);
  }
  if (t.header.empty()) throw InputError(path + ": empty file, expected a header row");
  return t;
}

void require_columns(const CsvTable& t, const std::vector<std::string>& names) {
  std::string expected, actual;
  for (size_t k = 0; k < names.size(); ++k) expected += (k ? "," : "") + names[k];
  for (size_t k = 0; k < t.header.size(); ++k) actual += (k ? "," : "") + t.header[k];
  bool ok = t.header.size() >= names.size();
  for (size_t k = 0; ok && k < names.size(); ++k) ok = t.header[k] == names[k];
  if (!ok) throw InputError(t.path + ":1: expected header starting '" + expected + "', found '" + quoted_text(actual) + "'");
}

}  // namespace icobrdf
