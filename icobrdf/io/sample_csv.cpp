#include "icobrdf/io/sample_csv.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/csv.hpp"

namespace icobrdf {

namespace {

// Plane-of-incidence test on sin(phi_r - phi_i): angles given to ~1e-9 deg count as in the plane.
constexpr double kPlaneTolerance = 1e-10;

std::string where(const CsvTable& t, size_t row) { return t.path + ":" + std::to_string(t.line_numbers[row]); }

std::string num(double x) {
  char b[64];
  std::snprintf(b, sizeof b, "%.10g", x);
  return b;
}

using Key = std::array<double, 4>;

// theta, phi in the file's unit; phi reduced to [0, full) and 0 at the pole.
void normalize(double& theta, double& phi, double full) {
  phi = std::fmod(phi, full);
  if (phi < 0) phi += full;
  if (phi >= full) phi = 0;  // fmod rounding of a value just below `full`
  if (theta == 0) phi = 0;
}

// A signed polar angle as NIST writes it: theta < 0 names the direction (|theta|, phi + 180 deg).
void unsign(double& theta, double& phi, double full) {
  if (theta < 0) {
    theta = -theta;
    phi += full / 2;
  }
}

// The key of a row: signed polar angles made positive, then normalized.
Key key_of(const std::vector<double>& row, double full) {
  Key key{row[0], row[1], row[2], row[3]};
  unsign(key[0], key[1], full);
  unsign(key[2], key[3], full);
  normalize(key[0], key[1], full);
  normalize(key[2], key[3], full);
  return key;
}

// The unit of the file's angles: declared by the option `radians`, by the column names (all four angles with
// the suffix _deg or all four with _rad, stripped from `t.header`) or by a comment line `# units: NAME`;
// degrees when none declares it. Declarations that disagree: InputError naming both.
struct AngleUnitChoice {
  bool radians = false;
  std::string declared_by;  // empty: assumed
};

AngleUnitChoice angle_unit_of(const CsvTable& t, const AngleColumns& columns, const SampleCsvOptions& options) {
  AngleUnitChoice u;
  auto declare = [&](bool radians, const std::string& by) {
    if (!u.declared_by.empty() && u.radians != radians)
      throw InputError(t.path + ": " + by + " declares " + (radians ? "radians" : "degrees") + " but " + u.declared_by +
                       " declares " + (u.radians ? "radians" : "degrees") + ", expected one unit for the angles");
    if (u.declared_by.empty()) u = {radians, by};
  };
  if (options.radians) declare(true, "the option 'radians'");
  // Column names: theta_i_deg ... or theta_i_rad ... (stripped by recognize_angle_columns).
  if (columns.unit_suffix_radians || columns.unit_suffix_degrees)
    declare(columns.unit_suffix_radians, std::string("the column names (") + (columns.unit_suffix_radians ? "_rad" : "_deg") + ")");
  for (const auto& [line, text] : t.comments) {
    std::string low = text;
    std::transform(low.begin(), low.end(), low.begin(), [](unsigned char c) { return std::tolower(c); });
    if (low.rfind("units:", 0) != 0) continue;
    std::string word = low.substr(6);
    word.erase(0, word.find_first_not_of(" \t"));
    word.erase(word.find_last_not_of(" \t") + 1);
    const std::string by = "line " + std::to_string(line) + " ('# " + quoted_text(text) + "')";
    if (word == "radians" || word == "rad") declare(true, by);
    else if (word == "degrees" || word == "deg") declare(false, by);
    else
      throw InputError(t.path + ":" + std::to_string(line) + ": units line expected 'degrees' or 'radians', found '" +
                       quoted_text(word) + "'");
  }
  return u;
}

// Reciprocal pairs: the swapped key present (each unordered pair once; a pair with w_i = w_r is its own
// partner and trivially reciprocal); counted into s, InputError under --strict for the first that differs.
void count_reciprocal_pairs(const std::string& path, const std::vector<Key>& keys, const std::map<Key, size_t>& index,
                            const SampleCsvOptions& options, BrdfSamples& s) {
  const int ch = s.channels;
  for (size_t k = 0; k < keys.size(); ++k) {
    const Key swapped{keys[k][2], keys[k][3], keys[k][0], keys[k][1]};
    const auto it = index.find(swapped);
    if (it == index.end() || it->second <= k) continue;
    ++s.reciprocal_pairs;
    double worst = 0;
    for (int c = 0; c < ch; ++c) {
      const double a = s.values(static_cast<Eigen::Index>(k), c), b = s.values(static_cast<Eigen::Index>(it->second), c);
      const double scale = std::max(std::abs(a), std::abs(b));
      if (scale > 0) worst = std::max(worst, std::abs(a - b) / scale);
    }
    s.max_reciprocity_difference = std::max(s.max_reciprocity_difference, worst);
    if (worst > options.reciprocity_tolerance) {
      ++s.nonreciprocal_pairs;
      if (options.strict)
        throw InputError(path + ":" + std::to_string(s.lines[k]) + ": sample and its reciprocal at line " +
                         std::to_string(s.lines[it->second]) + " differ by " + num(worst) +
                         " (relative), expected at most " + num(options.reciprocity_tolerance) + " (--strict)");
    }
  }
}

}  // namespace

BrdfSamples read_sample_csv(const std::string& path, const SampleCsvOptions& options) {
  if (!(options.reciprocity_tolerance >= 0) || !std::isfinite(options.reciprocity_tolerance))
    throw ArgumentError("CSV samples: reciprocity tolerance must be finite and >= 0");
  CsvTable t = read_numeric_csv(path);
  const AngleColumns columns = recognize_angle_columns(t, options.columns);
  const AngleUnitChoice unit_choice = angle_unit_of(t, columns, options);
  const int ch = static_cast<int>(t.header.size()) - columns.angles;
  if (ch != 1 && ch != 3)
    throw InputError(path + ":1: expected " + std::to_string(columns.angles + 1) + " columns (" + layout_name(columns.layout) +
                     ",value) or " + std::to_string(columns.angles + 3) + " (...,r,g,b), found " + std::to_string(t.header.size()));
  if (t.rows.empty()) throw InputError(path + ": no samples after the header, expected at least one data row");
  const bool radians = unit_choice.radians;
  const double full = radians ? 2 * M_PI : 360.0, quarter = full / 4;
  const double unit = radians ? 1.0 : M_PI / 180.0;
  const std::string qtext = radians ? "pi/2" : "90", ftext = radians ? "2 pi" : "360";

  // The extreme angles, for the unit checks.
  // The extreme angles of the file as written (zenith columns: theta_i, theta_r, sza, vza).
  double max_theta = 0, max_phi = 0;
  for (const auto& row : t.rows)
    for (int k = 0; k < columns.angles; ++k) {
      const bool zenith = t.header[static_cast<size_t>(k)] == "sza" || t.header[static_cast<size_t>(k)] == "vza" ||
                          t.header[static_cast<size_t>(k)].rfind("theta", 0) == 0;
      (zenith ? max_theta : max_phi) = std::max(zenith ? max_theta : max_phi, std::abs(row[static_cast<size_t>(k)]));
    }
  // Degrees assumed, yet every angle fits radians (every direction within 1.6 degrees of the normal): radians
  // read as degrees, whose fit would reach |f| ~ 1e9.
  if (unit_choice.declared_by.empty() && !radians && max_theta > 0 && max_theta <= M_PI / 2 && max_phi <= 2 * M_PI)
    throw InputError(path + ": every polar angle lies within [-" + num(M_PI / 2) + ", " + num(M_PI / 2) +
                     "] and every azimuth within [-" + num(2 * M_PI) + ", " + num(2 * M_PI) +
                     "]: these look like radians read as degrees (the default); declare the unit: the option 'radians' "
                     "(FILE.csv#radians), a line '# units: radians' or the suffix _rad on the angle columns (theta_i_rad,... or sza_rad,...) "
                     "('# units: degrees' if they are degrees)");
  // Radians declared, yet a polar angle exceeds pi/2 and the angles fit degrees (one beyond 2 pi).
  const bool degrees_like = radians && max_theta > M_PI / 2 && max_theta <= 90 && max_phi <= 360 && std::max(max_theta, max_phi) > 2 * M_PI;
  const std::string unit_note = (radians ? " radians (declared by " + unit_choice.declared_by + ")" : std::string(" degrees")) +
                                (degrees_like ? "; the file's angles look like degrees" : "");

  to_library_columns(t, columns, radians);

  BrdfSamples s;
  s.path = path;
  s.channels = ch;
  s.radians = radians;
  s.layout = columns.layout;
  s.quantity = columns.quantity;
  s.quantity_declared_by = columns.quantity_declared_by;
  s.header = columns.original_header;
  s.unit_declared_by = unit_choice.declared_by;
  s.rows = static_cast<long long>(t.rows.size());
  std::map<Key, size_t> index;  // normalized angles -> sample
  std::vector<Key> keys;
  std::vector<Eigen::VectorXd> sums;
  std::vector<double> counts;
  bool plane = true;
  for (size_t r = 0; r < t.rows.size(); ++r) {
    const auto& row = t.rows[r];
    for (int k : {0, 2})
      if (!(std::abs(row[k]) <= quarter))
        throw InputError(where(t, r) + ": column '" + quoted_text(columns.file_names[static_cast<size_t>(k)]) + "' expected a polar angle in [-" + qtext + ", " +
                         qtext + "]" + unit_note + ", found " + num(row[k]));
    for (int k : {1, 3})
      if (!(std::abs(row[k]) <= full))
        throw InputError(where(t, r) + ": column '" + quoted_text(columns.file_names[static_cast<size_t>(k)]) + "' expected an azimuth in [-" + ftext + ", " +
                         ftext + "]" + (degrees_like ? unit_note : std::string()) + ", found " + num(row[k]));
    if (row[0] < 0 || row[2] < 0) ++s.signed_theta_rows;
    Key key = key_of(row, full);
    Eigen::VectorXd v(ch);
    for (int c = 0; c < ch; ++c) {
      v[c] = row[4 + c];
      if (v[c] < 0) ++s.negative_values;
    }
    const auto it = index.find(key);
    if (it != index.end()) {
      sums[it->second] += v;
      counts[it->second] += 1;
      ++s.duplicates_merged;
      continue;
    }
    index.emplace(key, keys.size());
    keys.push_back(key);
    sums.push_back(v);
    counts.push_back(1);
    s.lines.push_back(t.line_numbers[r]);
    if (key[0] != 0 && key[2] != 0 && std::abs(std::sin((key[3] - key[1]) * unit)) > kPlaneTolerance) plane = false;
  }
  const auto n = static_cast<Eigen::Index>(keys.size());
  s.wi.resize(n, 3);
  s.wr.resize(n, 3);
  s.values.resize(n, ch);
  s.weights.resize(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const Key& key = keys[static_cast<size_t>(k)];
    s.wi.row(k) = direction_from_angles(key[0] * unit, key[1] * unit).transpose();
    s.wr.row(k) = direction_from_angles(key[2] * unit, key[3] * unit).transpose();
    s.values.row(k) = (sums[static_cast<size_t>(k)] / counts[static_cast<size_t>(k)]).transpose();
    s.weights[k] = counts[static_cast<size_t>(k)];
  }
  // Finite values near the double range can overflow in their sum; such means are taken again as sums of
  // value / count (each term finite, the mean lies between the extreme values).
  if (!s.values.allFinite()) {
    Eigen::MatrixXd scaled = Eigen::MatrixXd::Zero(n, ch);
    for (size_t r = 0; r < t.rows.size(); ++r) {
      const auto& row = t.rows[r];
      const Key key = key_of(row, full);
      const auto k = static_cast<Eigen::Index>(index.at(key));
      for (int c = 0; c < ch; ++c) scaled(k, c) += row[4 + c] / counts[static_cast<size_t>(k)];
    }
    for (Eigen::Index k = 0; k < n; ++k)
      if (!s.values.row(k).allFinite()) s.values.row(k) = scaled.row(k);
  }
  s.plane_of_incidence = plane;
  count_reciprocal_pairs(path, keys, index, options, s);
  return s;
}

}  // namespace icobrdf
