#pragma once
// Directions on the upper hemisphere: unit vectors (x, y, z), z >= 0, surface normal +z.
// (theta, phi): theta in [0, pi/2] from the normal, phi the azimuth from +x towards +y, in radians.
#include <Eigen/Core>

namespace icobrdf {

Eigen::Vector3d direction_from_angles(double theta, double phi);

struct Angles {
  double theta;  // [0, pi/2] for z >= 0
  double phi;    // (-pi, pi]; 0 at the pole
};
Angles angles_from_direction(const Eigen::Vector3d& unit_dir);

// Mirror direction (theta, phi + pi) and the same for retroreflection (identity): the two delta laws.
inline Eigen::Vector3d mirror_direction(const Eigen::Vector3d& d) { return {-d.x(), -d.y(), d.z()}; }

}  // namespace icobrdf
