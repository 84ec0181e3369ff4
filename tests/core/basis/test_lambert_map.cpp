// Lambert equal-area map: agreement with the trigonometric definition (eqs. 8-11), inverse, edges, errors.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/lambert_map.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

using icobrdf::lambert_from_disk;
using icobrdf::lambert_rho_squared;
using icobrdf::lambert_to_disk;

// Both maps are a handful of flops on O(1) values: agreement to a few ulps (eps = 2.2e-16).
constexpr double kTol = 1e-15;

Eigen::Vector3d dir(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

TEST(LambertMap, MatchesTrigonometricDefinition) {
  // rho = sqrt(2) sin(theta/2), disk point rho (cos phi, sin phi) (paper eqs. 10-11).
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> th(0.0, M_PI / 2), ph(-M_PI, M_PI);
  for (int i = 0; i < 1000; ++i) {
    const double theta = th(rng), phi = ph(rng);
    const Eigen::Vector2d p = lambert_to_disk(dir(theta, phi));
    const double rho = std::sqrt(2.0) * std::sin(theta / 2);
    EXPECT_NEAR(p.x(), rho * std::cos(phi), kTol);
    EXPECT_NEAR(p.y(), rho * std::sin(phi), kTol);
    EXPECT_NEAR(lambert_rho_squared(dir(theta, phi)), 1.0 - std::cos(theta), kTol);
  }
}

TEST(LambertMap, InverseRoundTrips) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> th(0.0, M_PI / 2), ph(-M_PI, M_PI), u(-1.0, 1.0);
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3d d = dir(th(rng), ph(rng));
    const Eigen::Vector3d back = lambert_from_disk(lambert_to_disk(d));
    EXPECT_NEAR((back - d).norm(), 0.0, kTol);
    Eigen::Vector2d p(u(rng), u(rng));
    if (p.norm() > 1.0) continue;
    const Eigen::Vector3d q = lambert_from_disk(p);
    EXPECT_NEAR(q.norm(), 1.0, kTol);
    EXPECT_GE(q.z(), 0.0);
    EXPECT_NEAR((lambert_to_disk(q) - p).norm(), 0.0, kTol);
  }
}

TEST(LambertMap, EqualArea) {
  // A polar cap of half-angle theta subtends 2 pi (1 - cos theta) sr; its image is the disk of radius rho,
  // area pi rho^2. Equal-area up to the constant 2 (dOmega = 2 dA) means rho^2 = 1 - cos theta.
  for (double theta : {0.01, 0.3, 1.0, 1.5, M_PI / 2}) {
    const double rho = lambert_to_disk(dir(theta, 0.4)).norm();
    EXPECT_NEAR(2.0 * M_PI * rho * rho, 2.0 * M_PI * (1.0 - std::cos(theta)), 2 * M_PI * kTol);
  }
}

TEST(LambertMap, PoleHorizonAndWrapAround) {
  EXPECT_EQ(lambert_to_disk({0, 0, 1}), Eigen::Vector2d(0, 0));
  EXPECT_EQ(lambert_from_disk({0, 0}), Eigen::Vector3d(0, 0, 1));
  // theta = 90 deg: the unit circle; z = cos(pi/2) ~ 6e-17 and a slightly negative z are both accepted.
  EXPECT_NEAR(lambert_to_disk(dir(M_PI / 2, 1.0)).norm(), 1.0, kTol);
  EXPECT_NEAR(lambert_to_disk({1.0, 0.0, -1e-17}).norm(), 1.0, kTol);
  EXPECT_NEAR(lambert_from_disk({0.6, 0.8}).z(), 0.0, kTol);
  // phi and phi +- 2 pi are the same direction, hence the same disk point.
  const Eigen::Vector2d a = lambert_to_disk(dir(0.7, 3.0)), b = lambert_to_disk(dir(0.7, 3.0 - 2 * M_PI));
  EXPECT_NEAR((a - b).norm(), 0.0, 4 * kTol);
}

TEST(LambertMap, RejectsPointsOutsideTheDomain) {
  EXPECT_THROW(lambert_to_disk({0.0, 0.6, -0.8}), icobrdf::ArgumentError);
  EXPECT_THROW(lambert_to_disk({0.0, 0.0, -1.0}), icobrdf::ArgumentError);
  EXPECT_THROW(lambert_rho_squared({0.0, 0.0, std::nan("")}), icobrdf::ArgumentError);
  EXPECT_THROW(lambert_from_disk({0.8, 0.7}), icobrdf::ArgumentError);
  EXPECT_THROW(lambert_from_disk({std::nan(""), 0.0}), icobrdf::ArgumentError);
}

}  // namespace ICOBRDF_UNITY_ID
