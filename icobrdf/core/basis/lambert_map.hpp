#pragma once
// Lambert's azimuthal equal-area map between the upper hemisphere and the unit disk (paper eqs. 8-12).
//
// A direction with polar angle theta (from the normal +z) and azimuth phi goes to the disk point
// rho (cos phi, sin phi) with rho = sqrt(2) sin(theta / 2), so rho^2 = 1 - cos(theta) and
// dOmega = 2 rho drho dphi = 2 dA: equal solid angles go to equal areas (the whole hemisphere, 2 pi sr,
// to the unit disk, pi). In Cartesian form, with no trigonometry:
//   to disk:    (x, y, z)  ->  (x, y) / sqrt(1 + z)
//   from disk:  p          ->  (p sqrt(2 - |p|^2), 1 - |p|^2)
// The pole (0, 0, 1) maps to the centre, the horizon z = 0 to the unit circle; azimuth is preserved.
// Accuracy: a few ulps in both directions over the whole hemisphere (the forward map never forms 1 - z).
#include <Eigen/Core>

namespace icobrdf {

// unit_dir: a unit vector with z >= 0 (z down to -kHorizonSlack, icobrdf/core/basis/horizon.hpp, is accepted as the
// horizon). Its length is not checked (the caller normalizes); z < -kHorizonSlack throws ArgumentError.
// Result: a point with |p| <= 1 (+ rounding).
Eigen::Vector2d lambert_to_disk(const Eigen::Vector3d& unit_dir);

// p: a disk point with |p| <= 1 (values up to 1 + kHorizonSlack are treated as on the circle); larger throws
// ArgumentError. Result: a unit vector with z >= 0.
Eigen::Vector3d lambert_from_disk(const Eigen::Vector2d& p);

// rho^2 = 1 - cos(theta) = |lambert_to_disk(unit_dir)|^2, computed as (x^2 + y^2) / (1 + z) (no cancellation
// near the pole); clamped to [0, 1]. Same preconditions as lambert_to_disk.
double lambert_rho_squared(const Eigen::Vector3d& unit_dir);

}  // namespace icobrdf
