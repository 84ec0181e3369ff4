#include "icobrdf/io/direction_csv.hpp"

#include <cmath>
#include <string>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/models/brdf_model.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/angle_columns.hpp"
#include "icobrdf/io/csv.hpp"

namespace icobrdf {
namespace {

// Signed polar angles: theta in [-90, 90] degrees; a negative theta is the direction (|theta|, phi + 180 deg),
// i.e. the other half of the plane of phi (goniometer convention).
Eigen::Vector3d signed_direction(const CsvTable& t, size_t row, size_t col, double theta, double phi, bool radians) {
  if (!(theta >= -M_PI / 2 && theta <= M_PI / 2))
    throw InputError(t.path + ":" + std::to_string(t.line_numbers[row]) + ": column '" + quoted_text(t.header[col]) +
                     "' expected a polar angle in [-" + (radians ? std::string("pi/2, pi/2") : std::string("90, 90")) +
                     "] (negative: the opposite azimuth), found " + std::to_string(t.rows[row][col]));
  return theta < 0 ? direction_from_angles(-theta, phi + M_PI) : direction_from_angles(theta, phi);
}

// Azimuth-like column `col` of `row` in radians: InputError beyond kMaxAzimuthTurns turns either way (1e308
// degrees would be evaluated at a meaningless angle: cos and sin of it keep no digit of the intended one).
double checked_azimuth(const CsvTable& t, size_t row, size_t col, bool radians) {
  const double v = t.rows[row][col], bound = kMaxAzimuthTurns * (radians ? 2 * M_PI : 360.0);
  if (!(std::abs(v) <= bound))
    throw InputError(t.path + ":" + std::to_string(t.line_numbers[row]) + ": column '" + quoted_text(t.header[col]) +
                     "' expected an azimuth in [-" + (radians ? std::string("4 pi, 4 pi") : std::string("720, 720")) +
                     "] (two turns), found " + format_parameter(v));
  return radians ? v : v * (M_PI / 180.0);  // the factor the polar angles are read with
}

Eigen::Vector3d to_direction(const CsvTable& t, size_t row, size_t col, bool radians) {
  const double unit = radians ? 1.0 : M_PI / 180.0;
  return signed_direction(t, row, col, t.rows[row][col] * unit, checked_azimuth(t, row, col + 1, radians), radians);
}

bool header_is(const CsvTable& t, const std::vector<std::string>& names) {
  if (t.header.size() < names.size()) return false;
  for (size_t k = 0; k < names.size(); ++k)
    if (t.header[k] != names[k]) return false;
  return true;
}

}  // namespace

DirectionPairs read_direction_pairs_csv(const std::string& path, bool radians) {
  CsvTable t = read_numeric_csv(path);
  const bool scatmech = header_is(t, {"thetai", "thetas", "phis"});
  const bool remote_sensing = header_is(t, {"sza", "vza", "raa"}) || header_is(t, {"sza", "saa", "vza", "vaa"});
  if (!scatmech && !remote_sensing && !header_is(t, {"theta_i", "phi_i", "theta_r", "phi_r"})) {
    std::string found;
    for (const auto& h : t.header) found += (found.empty() ? "" : ",") + h;
    throw InputError(t.path + ":1: expected the header theta_i,phi_i,theta_r,phi_r, sza,vza,raa, sza,saa,vza,vaa or SCATMECH's "
                     "thetai,thetas,phis[,rotation], found '" + quoted_text(found) + "'");
  }
  if (remote_sensing) {  // the library's columns (icobrdf/io/angle_columns.hpp); extra columns are ignored
    AngleColumnOptions o;
    o.values_expected = false;
    to_library_columns(t, recognize_angle_columns(t, o), radians);
  }
  const bool rotation = scatmech && t.header.size() > 3 && t.header[3] == "rotation";
  DirectionPairs p;
  p.wi.resize(static_cast<Eigen::Index>(t.rows.size()), 3);
  p.wr.resize(static_cast<Eigen::Index>(t.rows.size()), 3);
  const double unit = radians ? 1.0 : M_PI / 180.0;
  for (size_t r = 0; r < t.rows.size(); ++r) {
    const auto at = static_cast<Eigen::Index>(r);
    if (scatmech) {
      // SCATMECH's frame: the source at azimuth pi, phis = 0 the forward half of the plane of incidence; the
      // sample turned by `rotation` about its normal, so its azimuths are the frame's minus rotation.
      const double rot = rotation ? checked_azimuth(t, r, 3, radians) : 0.0;
      p.wi.row(at) = signed_direction(t, r, 0, t.rows[r][0] * unit, M_PI - rot, radians).transpose();
      p.wr.row(at) = signed_direction(t, r, 1, t.rows[r][1] * unit, checked_azimuth(t, r, 2, radians) - rot, radians).transpose();
    } else {
      p.wi.row(at) = to_direction(t, r, 0, radians).transpose();
      p.wr.row(at) = to_direction(t, r, 2, radians).transpose();
    }
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
