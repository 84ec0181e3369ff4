#include "icobrdf/pipeline/bank_candidates.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/bank_file.hpp"

namespace icobrdf {
namespace {

constexpr const char* kMagic = "icobrdf-candidates";
constexpr const char* kHeader = "representation,bytes,error_l2";

std::string trimmed(const std::string& s) {
  const auto a = s.find_first_not_of(' '), b = s.find_last_not_of(' ');
  return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
}

}  // namespace

std::string candidates_text(std::vector<CandidatePoint> points) {
  std::sort(points.begin(), points.end(), [](const CandidatePoint& a, const CandidatePoint& b) {
    return a.representation != b.representation ? a.representation < b.representation
           : a.bytes != b.bytes                 ? a.bytes < b.bytes
                                                : a.error_l2 < b.error_l2;
  });
  std::vector<CandidatePoint> kept;
  for (const auto& p : points)
    if (kept.empty() || kept.back().representation != p.representation || kept.back().bytes != p.bytes) kept.push_back(p);
  if (kept.size() > kMaxCandidatePoints) {
    std::stable_sort(kept.begin(), kept.end(), [](const CandidatePoint& a, const CandidatePoint& b) { return a.bytes < b.bytes; });
    kept.resize(kMaxCandidatePoints);
  }
  std::string t = fmt::format("{} {}; {}", kMagic, kCandidatesVersion, kHeader);
  for (const auto& p : kept) t += fmt::format("; {},{},{:.17g}", p.representation, p.bytes, p.error_l2);
  return t;
}

std::vector<CandidatePoint> parse_candidates(const std::string& text, const std::string& where) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  for (std::string part; std::getline(in, part, ';');) parts.push_back(trimmed(part));
  const std::string head = fmt::format("{} {}", kMagic, kCandidatesVersion);
  if (parts.size() < 2 || parts[0].rfind(kMagic, 0) != 0)
    throw InputError(where + ": label candidates: expected '" + head + "; " + kHeader + "; ...', found '" + text.substr(0, 60) + "'");
  if (parts[0] != head)
    throw InputError(where + ": label candidates: version '" + parts[0] + "', this program reads '" + head + "'");
  if (parts[1] != kHeader) throw InputError(where + ": label candidates: columns '" + parts[1] + "', expected '" + kHeader + "'");
  std::vector<CandidatePoint> out;
  for (std::size_t k = 2; k < parts.size(); ++k) {
    const auto c1 = parts[k].find(','), c2 = parts[k].find(',', c1 == std::string::npos ? c1 : c1 + 1);
    CandidatePoint p;
    char* end1 = nullptr;
    char* end2 = nullptr;
    if (c1 != std::string::npos && c2 != std::string::npos) {
      p.representation = parts[k].substr(0, c1);
      const std::string b = parts[k].substr(c1 + 1, c2 - c1 - 1), e = parts[k].substr(c2 + 1);
      p.bytes = std::strtoll(b.c_str(), &end1, 10);
      p.error_l2 = std::strtod(e.c_str(), &end2);
      if (!b.empty() && !e.empty() && *end1 == '\0' && *end2 == '\0' && p.bytes > 0 && std::isfinite(p.error_l2) && p.error_l2 >= 0 &&
          !p.representation.empty()) {
        out.push_back(p);
        continue;
      }
    }
    throw InputError(where + ": label candidates: entry " + std::to_string(k - 1) + " '" + parts[k] +
                     "': expected REPRESENTATION,BYTES,ERROR with BYTES > 0 and ERROR >= 0");
  }
  return out;
}

BankMaterialCandidates read_bank_candidates(const std::string& text) {
  const MaterialRef ref = split_material_ref(text);
  if (ref.name.empty()) {
    const auto names = bank_material_names(ref.path);
    if (names.size() > 1)
      throw ArgumentError("'" + quoted_text(text) + "' holds " + std::to_string(names.size()) + " materials: name one, BANK.h5#" + names.front());
  }
  ReadOptions o;
  o.read_luts = false;
  const MaterialRecord rec = read_bank_material(ref.path, ref.name, o);
  const std::string where = ref.path + " material '" + rec.name + "'";
  for (const char* k : {"target", "bytes", "error_l2"})
    if (!rec.figures.count(k)) throw InputError(where + ": no figure '" + k + "' of a bank build (a spectrum file, not a bank material?)");
  BankMaterialCandidates c;
  c.name = rec.name;
  c.target = rec.figures.at("target");
  c.chosen = {representation_name(rec), static_cast<long long>(rec.figures.at("bytes")), rec.figures.at("error_l2")};
  const auto it = rec.labels.find(kCandidatesLabel);
  if (it != rec.labels.end()) c.points = parse_candidates(it->second, where);
  return c;
}

}  // namespace icobrdf
