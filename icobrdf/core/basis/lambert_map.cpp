#include "icobrdf/core/basis/lambert_map.hpp"

#include <cmath>
#include <string>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/horizon.hpp"

namespace icobrdf {

namespace {

double checked_z(const Eigen::Vector3d& u, const char* where) {
  if (!(u.z() >= -kHorizonSlack))
    throw ArgumentError(std::string(where) + ": direction must lie in the upper hemisphere (z >= 0), got z = " +
                        std::to_string(u.z()));
  return u.z() < 0.0 ? 0.0 : u.z();
}

}  // namespace

Eigen::Vector2d lambert_to_disk(const Eigen::Vector3d& unit_dir) {
  const double z = checked_z(unit_dir, "lambert_to_disk");
  return unit_dir.head<2>() / std::sqrt(1.0 + z);
}

double lambert_rho_squared(const Eigen::Vector3d& unit_dir) {
  const double z = checked_z(unit_dir, "lambert_rho_squared");
  const double r2 = unit_dir.head<2>().squaredNorm() / (1.0 + z);
  return r2 > 1.0 ? 1.0 : r2;
}

Eigen::Vector3d lambert_from_disk(const Eigen::Vector2d& p) {
  double r2 = p.squaredNorm();
  if (!(r2 <= 1.0 + kHorizonSlack))
    throw ArgumentError("Lambert map: point must lie in the unit disk, got |p| = " +
                        std::to_string(std::sqrt(r2)));
  if (r2 > 1.0) r2 = 1.0;
  const double s = std::sqrt(2.0 - r2);
  return Eigen::Vector3d(p.x() * s, p.y() * s, 1.0 - r2);
}

}  // namespace icobrdf
