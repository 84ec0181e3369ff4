#pragma once
// Directions on the upper hemisphere: unit vectors (x, y, z), z >= 0, surface normal +z.
// (theta, phi): theta in [0, pi/2] from the normal, phi the azimuth from +x towards +y, in radians.
#include <Eigen/Core>

#include <random>

namespace icobrdf {

Eigen::Vector3d direction_from_angles(double theta, double phi);

struct Angles {
  double theta;  // [0, pi/2] for z >= 0
  double phi;    // (-pi, pi]; 0 at the pole
};
Angles angles_from_direction(const Eigen::Vector3d& unit_dir);

// A direction uniform in solid angle over the band cos(theta) in [z_lo, z_hi] of the upper hemisphere (z
// uniform in the band), from two draws of `rng` in a fixed order: the azimuth in [-pi, pi), then z. Every
// random direction set of icobrdf (held-out pairs of banks and of the sweep, hard-case probes) comes from
// here, so a seed gives the same directions everywhere and with any compiler (draws in separate statements).
Eigen::Vector3d uniform_direction(std::mt19937_64& rng, double z_lo = 0.0, double z_hi = 1.0);

// Mirror direction (theta, phi + pi) and the same for retroreflection (identity): the two delta laws.
inline Eigen::Vector3d mirror_direction(const Eigen::Vector3d& d) { return {-d.x(), -d.y(), d.z()}; }

}  // namespace icobrdf
