#include "icobrdf/io/sample_csv.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>

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

}  // namespace

BrdfSamples read_sample_csv(const std::string& path, const SampleCsvOptions& options) {
  if (!(options.reciprocity_tolerance >= 0) || !std::isfinite(options.reciprocity_tolerance))
    throw ArgumentError("CSV samples: reciprocity tolerance must be finite and >= 0");
  const CsvTable t = read_numeric_csv(path);
  require_columns(t, {"theta_i", "phi_i", "theta_r", "phi_r"});
  if (t.header.size() != 5 && t.header.size() != 7)
    throw InputError(path + ":1: expected 5 columns (theta_i,phi_i,theta_r,phi_r,value) or 7 (...,r,g,b), found " +
                     std::to_string(t.header.size()));
  if (t.rows.empty()) throw InputError(path + ": no samples after the header, expected at least one data row");
  const int ch = static_cast<int>(t.header.size()) - 4;
  const double full = options.radians ? 2 * M_PI : 360.0, quarter = full / 4;
  const double unit = options.radians ? 1.0 : M_PI / 180.0;
  const std::string qtext = options.radians ? "pi/2" : "90", ftext = options.radians ? "2 pi" : "360";

  BrdfSamples s;
  s.path = path;
  s.channels = ch;
  s.rows = static_cast<long long>(t.rows.size());
  std::map<Key, size_t> index;  // normalized angles -> sample
  std::vector<Key> keys;
  std::vector<Eigen::VectorXd> sums;
  std::vector<double> counts;
  bool plane = true;
  for (size_t r = 0; r < t.rows.size(); ++r) {
    const auto& row = t.rows[r];
    for (int k : {0, 2})
      if (!(row[k] >= 0 && row[k] <= quarter))
        throw InputError(where(t, r) + ": column '" + quoted_text(t.header[k]) + "' expected a polar angle in [0, " + qtext +
                         "], found " + num(row[k]));
    for (int k : {1, 3})
      if (!(std::abs(row[k]) <= full))
        throw InputError(where(t, r) + ": column '" + quoted_text(t.header[k]) + "' expected an azimuth in [-" + ftext + ", " +
                         ftext + "], found " + num(row[k]));
    Key key{row[0], row[1], row[2], row[3]};
    normalize(key[0], key[1], full);
    normalize(key[2], key[3], full);
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
      Key key{row[0], row[1], row[2], row[3]};
      normalize(key[0], key[1], full);
      normalize(key[2], key[3], full);
      const auto k = static_cast<Eigen::Index>(index.at(key));
      for (int c = 0; c < ch; ++c) scaled(k, c) += row[4 + c] / counts[static_cast<size_t>(k)];
    }
    for (Eigen::Index k = 0; k < n; ++k)
      if (!s.values.row(k).allFinite()) s.values.row(k) = scaled.row(k);
  }
  s.plane_of_incidence = plane;
  // Reciprocal pairs: the swapped key present (each unordered pair once; a pair with w_i = w_r is its own
  // partner and trivially reciprocal).
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
  return s;
}

}  // namespace icobrdf
