#include "icobrdf/io/angle_columns.hpp"

#include <cmath>

#include "icobrdf/core/support/error.hpp"

namespace icobrdf {
namespace {

const std::vector<std::string> kLibraryAngleNames{"theta_i", "phi_i", "theta_r", "phi_r"};
const std::vector<std::string> kRelativeAngleNames{"sza", "vza", "raa"};
const std::vector<std::string> kAzimuthAngleNames{"sza", "saa", "vza", "vaa"};

bool name_ends_with(const std::string& s, const std::string& tail) {
  return s.size() > tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}
bool name_starts_with(const std::string& s, const std::string& head) { return s.rfind(head, 0) == 0; }

std::string joined_names(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ",") + n;
  return out;
}

// The header's names with a _deg or _rad suffix removed from the names that are angles once stripped.
struct StrippedHeader {
  std::vector<std::string> names;
  int deg = 0, rad = 0;
};

bool is_angle_column_name(const std::string& n) {
  for (const auto* list : {&kLibraryAngleNames, &kRelativeAngleNames, &kAzimuthAngleNames})
    for (const auto& a : *list)
      if (n == a) return true;
  return false;
}

StrippedHeader strip_unit_suffixes(const std::vector<std::string>& header) {
  StrippedHeader s{header, 0, 0};
  for (auto& n : s.names)
    for (const char* tail : {"_deg", "_rad"}) {
      const std::string t = tail;
      if (name_ends_with(n, t) && is_angle_column_name(n.substr(0, n.size() - t.size()))) {
        n.erase(n.size() - t.size());
        ++(t == "_deg" ? s.deg : s.rad);
      }
    }
  return s;
}

bool header_begins_with(const std::vector<std::string>& header, const std::vector<std::string>& names) {
  if (header.size() < names.size()) return false;
  for (size_t k = 0; k < names.size(); ++k)
    if (header[k] != names[k]) return false;
  return true;
}

// The quantity a value column's name declares: 1 BRF, -1 BRDF, 0 none.
int quantity_of_name(const std::string& n) {
  if (n == "brf" || n == "rho" || name_starts_with(n, "brf_")) return 1;
  if (n == "brdf" || n == "f" || name_starts_with(n, "brdf_")) return -1;
  return 0;
}

}  // namespace

std::string layout_name(AngleLayout layout) {
  switch (layout) {
    case AngleLayout::Library: return joined_names(kLibraryAngleNames);
    case AngleLayout::SunViewRelative: return joined_names(kRelativeAngleNames);
    case AngleLayout::SunViewAzimuths: return joined_names(kAzimuthAngleNames);
  }
  return "";
}

AngleColumns recognize_angle_columns(CsvTable& t, const AngleColumnOptions& options) {
  AngleColumns c;
  c.original_header = joined_names(t.header);
  const std::string at = t.path + ":1: ";
  if (!options.names.empty()) {
    if (options.names.size() != t.header.size())
      throw InputError(at + "the option columns= names " + std::to_string(options.names.size()) + " columns (" + joined_names(options.names) +
                       "), expected the file's " + std::to_string(t.header.size()) + " (" + c.original_header + ")");
    t.header = options.names;
  }
  const StrippedHeader s = strip_unit_suffixes(t.header);
  if (header_begins_with(s.names, kLibraryAngleNames)) c.layout = AngleLayout::Library, c.angles = 4;
  else if (header_begins_with(s.names, kAzimuthAngleNames)) c.layout = AngleLayout::SunViewAzimuths, c.angles = 4;
  else if (header_begins_with(s.names, kRelativeAngleNames)) c.layout = AngleLayout::SunViewRelative, c.angles = 3;
  else
    throw InputError(at + "expected header starting 'theta_i,phi_i,theta_r,phi_r' (the library's), 'sza,vza,raa' or "
                          "'sza,saa,vza,vaa' (remote sensing; degrees, or the suffix _rad), found '" +
                     quoted_text(joined_names(t.header)) + "' (the option columns=NAME/NAME/... renames the columns)");
  if (s.deg + s.rad > 0 && s.deg != c.angles && s.rad != c.angles)
    throw InputError(at + "the angle columns carry " + std::to_string(s.deg) + " '_deg' and " + std::to_string(s.rad) +
                     " '_rad' suffixes, expected the same suffix on all " + std::to_string(c.angles) + " or none");
  if (c.layout == AngleLayout::SunViewRelative) c.file_names = {t.header[0], "", t.header[1], t.header[2]};
  else c.file_names = {t.header[0], t.header[1], t.header[2], t.header[3]};
  c.unit_suffix_radians = s.rad == c.angles;
  c.unit_suffix_degrees = s.deg == c.angles;
  t.header = s.names;

  // The values' quantity: the option, else the names.
  if (!options.values.empty()) {
    if (options.values != "brf" && options.values != "brdf")
      throw ArgumentError(t.path + ": the option values= expected 'brf' or 'brdf', found '" + quoted_text(options.values) + "'");
    c.quantity = options.values == "brf" ? ValueQuantity::Brf : ValueQuantity::Brdf;
    c.quantity_declared_by = "the option values=" + options.values;
    return c;
  }
  int brf = 0, brdf = 0, other = 0;
  std::string unknown;
  for (size_t k = static_cast<size_t>(c.angles); k < t.header.size(); ++k) {
    const int q = quantity_of_name(t.header[k]);
    (q > 0 ? brf : q < 0 ? brdf : other) += 1;
    if (q == 0 && unknown.empty()) unknown = t.header[k];
  }
  if (brf > 0 && (brdf > 0 || other > 0))
    throw InputError(at + "the value columns name " + std::to_string(brf) + " BRF column(s) (brf, rho, brf_*) among others (" +
                     joined_names(std::vector<std::string>(t.header.begin() + c.angles, t.header.end())) +
                     "), expected one quantity for every value column (or the option values=brf|brdf)");
  if (brf > 0) {
    c.quantity = ValueQuantity::Brf;
    c.quantity_declared_by = "the column names";
  } else if (brdf > 0 && other == 0) {
    c.quantity_declared_by = "the column names";
  } else if (other > 0 && c.layout != AngleLayout::Library && options.values_expected) {
    throw InputError(at + "value column '" + quoted_text(unknown) + "' does not say its quantity, expected brf (BRF = pi f), rho, "
                          "brf_NAME, or brdf, f, brdf_NAME (1/sr) after " + layout_name(c.layout) +
                     " (or the option values=brf|brdf)");
  }
  return c;
}

void to_library_columns(CsvTable& t, const AngleColumns& c, bool radians) {
  const double quarter = radians ? M_PI / 2 : 90.0;
  const double scale = c.quantity == ValueQuantity::Brf ? 1.0 / M_PI : 1.0;
  for (auto& row : t.rows) {
    std::vector<double> out(4 + row.size() - static_cast<size_t>(c.angles));
    switch (c.layout) {
      case AngleLayout::Library: out[0] = row[0], out[1] = row[1], out[2] = row[2], out[3] = row[3]; break;
      case AngleLayout::SunViewRelative: out[0] = row[0], out[1] = 0.0, out[2] = row[1], out[3] = row[2]; break;
      // Compass azimuths (clockwise from north) to the library's (counterclockwise from +x = east).
      case AngleLayout::SunViewAzimuths: out[0] = row[0], out[1] = quarter - row[1], out[2] = row[2], out[3] = quarter - row[3]; break;
    }
    for (size_t k = static_cast<size_t>(c.angles); k < row.size(); ++k) out[4 + k - static_cast<size_t>(c.angles)] = row[k] * scale;
    row = std::move(out);
  }
  std::vector<std::string> header = kLibraryAngleNames;
  header.insert(header.end(), t.header.begin() + c.angles, t.header.end());
  t.header = std::move(header);
}

}  // namespace icobrdf
