#include "icobrdf/core/basis/direction.hpp"

#include <cmath>

namespace icobrdf {

Eigen::Vector3d direction_from_angles(double theta, double phi) {
  const double s = std::sin(theta);
  return {s * std::cos(phi), s * std::sin(phi), std::cos(theta)};
}

Angles angles_from_direction(const Eigen::Vector3d& d) {
  // atan2 of (sin, cos) keeps full relative accuracy near the pole, where acos(z) would not.
  const double s = std::hypot(d.x(), d.y());
  return {std::atan2(s, d.z()), s > 0.0 ? std::atan2(d.y(), d.x()) : 0.0};
}

Eigen::Vector3d uniform_direction(std::mt19937_64& rng, double z_lo, double z_hi) {
  std::uniform_real_distribution<double> azimuth(-M_PI, M_PI), z(z_lo, z_hi);
  const double phi = azimuth(rng);
  const double cos_theta = z(rng);
  return direction_from_angles(std::acos(cos_theta), phi);
}

}  // namespace icobrdf
