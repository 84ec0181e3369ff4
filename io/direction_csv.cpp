#include "io/direction_csv.hpp"

#include <cmath>
#include <string>

#include "core/direction.hpp"
#include "core/error.hpp"
#include "io/csv.hpp"

namespace icobrdf {
namespace {

Eigen::Vector3d to_direction(const CsvTable& t, size_t row, size_t col, bool radians) {
  const double unit = radians ? 1.0 : M_PI / 180.0;
  const double theta = t.rows[row][col] * unit, phi = t.rows[row][col + 1] * unit;
  if (theta < 0.0 || theta > M_PI / 2)
    throw InputError(t.path + ":" + std::to_string(t.line_numbers[row]) + ": column '" + quoted_text(t.header[col]) +
                     "' expected a polar angle in [0, " + (radians ? std::string("pi/2") : std::string("90")) +
                     "], found " + std::to_string(t.rows[row][col]));
  return direction_from_angles(theta, phi);
}

}  // namespace

DirectionPairs read_direction_pairs_csv(const std::string& path, bool radians) {
  const CsvTable t = read_numeric_csv(path);
  require_columns(t, {"theta_i", "phi_i", "theta_r", "phi_r"});
  DirectionPairs p;
  p.wi.resize(static_cast<Eigen::Index>(t.rows.size()), 3);
  p.wr.resize(static_cast<Eigen::Index>(t.rows.size()), 3);
  for (size_t r = 0; r < t.rows.size(); ++r) {
    p.wi.row(static_cast<Eigen::Index>(r)) = to_direction(t, r, 0, radians).transpose();
    p.wr.row(static_cast<Eigen::Index>(r)) = to_direction(t, r, 2, radians).transpose();
  }
  p.lines = t.line_numbers;
  return p;
}

RowMatrix3d read_directions_csv(const std::string& path, bool radians) {
  const CsvTable t = read_numeric_csv(path);
  require_columns(t, {"theta", "phi"});
  RowMatrix3d d(static_cast<Eigen::Index>(t.rows.size()), 3);
  for (size_t r = 0; r < t.rows.size(); ++r) d.row(static_cast<Eigen::Index>(r)) = to_direction(t, r, 0, radians).transpose();
  return d;
}

}  // namespace icobrdf
