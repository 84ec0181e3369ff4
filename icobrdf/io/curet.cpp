#include "icobrdf/io/curet.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/support/error.hpp"

namespace icobrdf {
namespace {

// Plane-of-incidence test on sin(phi_r - phi_i), as the CSV reader's.
constexpr double kCuretPlaneTolerance = 1e-10;

struct NumberLine {
  int line = 0;
  std::vector<double> fields;
};

// The non-blank lines of a text file as numbers (file:line errors).
std::vector<NumberLine> read_number_lines(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open for reading");
  std::vector<NumberLine> out;
  std::string text;
  int line = 0;
  while (std::getline(in, text)) {
    ++line;
    if (!text.empty() && text.back() == '\r') text.pop_back();
    std::istringstream ss(text);
    std::string field;
    NumberLine n{line, {}};
    while (ss >> field) {
      char* end = nullptr;
      errno = 0;
      const double v = std::strtod(field.c_str(), &end);
      if (end != field.c_str() + field.size() || errno == ERANGE || !std::isfinite(v))
        throw InputError(path + ":" + std::to_string(line) + ": field " + std::to_string(n.fields.size() + 1) +
                         " expected a finite number, found '" + quoted_text(field) + "'");
      n.fields.push_back(v);
    }
    if (!n.fields.empty()) out.push_back(std::move(n));
  }
  if (out.empty()) throw InputError(path + ": empty file, expected CURET lines of numbers");
  return out;
}

std::string curet_number(double x) {
  char b[64];
  std::snprintf(b, sizeof b, "%.10g", x);
  return b;
}

// |phi_a - phi_b| reduced to [0, pi].
double azimuth_gap(double a, double b) {
  double d = std::fmod(std::abs(a - b), 2 * M_PI);
  return d > M_PI ? 2 * M_PI - d : d;
}

}  // namespace

std::string curet_table_beside(const std::string& brdf_path) {
  const auto slash = brdf_path.rfind('/');
  return slash == std::string::npos ? "table.txt" : brdf_path.substr(0, slash + 1) + "table.txt";
}

CuretDatabase read_curet(const std::string& brdf_path, const std::string& table_path) {
  CuretDatabase db;
  db.brdf_path = brdf_path;
  db.table_path = table_path;
  const std::vector<NumberLine> table = read_number_lines(table_path);
  const auto g = static_cast<Eigen::Index>(table.size());
  db.wi.resize(g, 3);
  db.wr.resize(g, 3);
  std::vector<std::array<double, 4>> angles;  // theta_v, phi_v, theta_i, phi_i
  for (Eigen::Index k = 0; k < g; ++k) {
    const NumberLine& t = table[static_cast<size_t>(k)];
    const std::string where = table_path + ":" + std::to_string(t.line);
    if (t.fields.size() != 5)
      throw InputError(where + ": expected 5 fields (index theta_v phi_v theta_i phi_i), found " + std::to_string(t.fields.size()));
    if (t.fields[0] != static_cast<double>(k + 1))
      throw InputError(where + ": expected geometry index " + std::to_string(k + 1) + ", found " + curet_number(t.fields[0]));
    static const char* names[] = {"theta_v", "phi_v", "theta_i", "phi_i"};
    for (int a : {1, 3})
      if (!(t.fields[a] >= 0 && t.fields[a] <= M_PI / 2))
        throw InputError(where + ": " + names[a - 1] + " expected a polar angle in [0, pi/2] radians, found " + curet_number(t.fields[a]) +
                         (t.fields[a] > M_PI / 2 && t.fields[a] <= 90 ? " (degrees? the CURET table is in radians)" : ""));
    for (int a : {2, 4})
      if (!(std::abs(t.fields[a]) <= 2 * M_PI))
        throw InputError(where + ": " + names[a - 1] + " expected an azimuth in [-2 pi, 2 pi] radians, found " + curet_number(t.fields[a]));
    db.wr.row(k) = direction_from_angles(t.fields[1], t.fields[2]).transpose();
    db.wi.row(k) = direction_from_angles(t.fields[3], t.fields[4]).transpose();
    angles.push_back({t.fields[1], t.fields[2], t.fields[3], t.fields[4]});
  }
  for (Eigen::Index a = 0; a < g; ++a)
    for (Eigen::Index b = a + 1; b < g; ++b) {
      const auto& p = angles[static_cast<size_t>(a)];
      const auto& q = angles[static_cast<size_t>(b)];
      if (std::abs(p[0] - q[2]) <= kCuretReciprocalTolerance && std::abs(p[2] - q[0]) <= kCuretReciprocalTolerance &&
          std::abs(azimuth_gap(p[1], p[3]) - azimuth_gap(q[1], q[3])) <= kCuretReciprocalTolerance)
        db.reciprocal_pairs.emplace_back(static_cast<int>(a), static_cast<int>(b));
    }

  const std::vector<NumberLine> brdf = read_number_lines(brdf_path);
  db.values.resize(static_cast<Eigen::Index>(brdf.size()), g);
  std::map<int, int> seen;  // sample number -> line
  for (size_t s = 0; s < brdf.size(); ++s) {
    const NumberLine& b = brdf[s];
    const std::string where = brdf_path + ":" + std::to_string(b.line);
    if (b.fields.size() != static_cast<size_t>(g) + 1)
      throw InputError(where + ": expected " + std::to_string(g + 1) + " fields (sample number, then the BRDF at the " +
                       std::to_string(g) + " geometries of " + table_path + "), found " + std::to_string(b.fields.size()));
    const double n = b.fields[0];
    if (!(n >= 1 && n == std::floor(n) && n < 1e9))
      throw InputError(where + ": expected a sample number >= 1 in field 1, found " + curet_number(n));
    const auto [it, fresh] = seen.emplace(static_cast<int>(n), b.line);
    if (!fresh)
      throw InputError(where + ": sample " + curet_number(n) + " repeats line " + std::to_string(it->second) + ", expected each sample once");
    db.sample_numbers.push_back(static_cast<int>(n));
    for (Eigen::Index k = 0; k < g; ++k) db.values(static_cast<Eigen::Index>(s), k) = b.fields[static_cast<size_t>(k) + 1];
  }
  return db;
}

BrdfSamples curet_samples(const CuretDatabase& db, int number) {
  const auto it = std::find(db.sample_numbers.begin(), db.sample_numbers.end(), number);
  if (it == db.sample_numbers.end())
    throw ArgumentError("CURET " + db.brdf_path + ": no sample " + std::to_string(number) + ", expected one of " +
                        std::to_string(*std::min_element(db.sample_numbers.begin(), db.sample_numbers.end())) + ".." +
                        std::to_string(*std::max_element(db.sample_numbers.begin(), db.sample_numbers.end())));
  const auto row = static_cast<Eigen::Index>(it - db.sample_numbers.begin());
  const Eigen::Index g = db.wi.rows();
  BrdfSamples s;
  s.path = db.brdf_path;
  s.channels = 1;
  s.wi = db.wi;
  s.wr = db.wr;
  s.values = db.values.row(row).transpose();
  s.weights = Eigen::VectorXd::Ones(g);
  s.rows = g;
  s.radians = true;
  s.unit_declared_by = "the CURET format";
  bool plane = true;
  for (Eigen::Index k = 0; k < g; ++k) {
    s.lines.push_back(static_cast<int>(k + 1));
    if (s.values(k, 0) < 0) ++s.negative_values;
    const double cross = db.wi(k, 0) * db.wr(k, 1) - db.wi(k, 1) * db.wr(k, 0);  // sin(dphi) sin(theta_i) sin(theta_v)
    const double si = db.wi.row(k).head<2>().norm(), sr = db.wr.row(k).head<2>().norm();
    if (si > 0 && sr > 0 && std::abs(cross) / (si * sr) > kCuretPlaneTolerance) plane = false;
  }
  s.plane_of_incidence = plane;
  for (const auto& [a, b] : db.reciprocal_pairs) {
    ++s.reciprocal_pairs;
    const double x = s.values(a, 0), y = s.values(b, 0), scale = std::max(std::abs(x), std::abs(y));
    const double d = scale > 0 ? std::abs(x - y) / scale : 0.0;
    s.max_reciprocity_difference = std::max(s.max_reciprocity_difference, d);
    if (d > SampleCsvOptions{}.reciprocity_tolerance) ++s.nonreciprocal_pairs;
  }
  return s;
}

}  // namespace icobrdf
