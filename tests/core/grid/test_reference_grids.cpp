#include <gtest/gtest.h>

#include <cmath>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/core/grid/reference_grids.hpp"
#include "tests/support/unity_id.hpp"

// Sums of up to a few thousand O(1e-3) weights: 1e-13 relative allows their rounding.
constexpr double kSumTol = 1e-13;
// Directions from sin/cos: a few ulps.
constexpr double kDirTol = 1e-14;

namespace ICOBRDF_UNITY_ID {

// Checks that map[c] contains the image of cell c's cubature points under `image` (by nearest direction
// among the image cell's points — here grids are symmetric node-for-node).
template <class F>
void expect_symmetry(const icobrdf::Grid& g, const Eigen::VectorXi& map, F image) {
  for (int c = 0; c < g.cells(); ++c) {
    const Eigen::Vector3d want = image(Eigen::Vector3d(g.directions.row(c).transpose()));
    EXPECT_LT((g.directions.row(map[c]).transpose() - want).norm(), kDirTol) << "cell " << c;
  }
}

TEST(PolarGaussGrid, ValidSumsToTwoPiAndIntegratesCosine) {
  const auto g = icobrdf::build_polar_gauss_grid(5, 12);
  EXPECT_NO_THROW(icobrdf::validate(g));
  EXPECT_NEAR(g.solid_angles.sum(), 2 * M_PI, kSumTol * 2 * M_PI);
  // integral cos(theta) dOmega over the hemisphere = pi; cos = 1 - t is degree 1 in t.
  EXPECT_NEAR(g.directions.col(2).dot(g.solid_angles), M_PI, kSumTol * M_PI);
  // integral cos^9 dOmega = 2 pi / 10: degree 9 in t needs 5 rings (exact up to degree 9).
  EXPECT_NEAR(g.directions.col(2).array().pow(9).matrix().dot(g.solid_angles), 2 * M_PI / 10, kSumTol);
}

TEST(PolarGaussGrid, SymmetryMapsAreExact) {
  const auto g = icobrdf::build_polar_gauss_grid(3, 8);
  expect_symmetry(g, g.rotate_pi, [](Eigen::Vector3d d) { return icobrdf::mirror_direction(d); });
  expect_symmetry(g, g.mirror_xz, [](Eigen::Vector3d d) { return Eigen::Vector3d(d.x(), -d.y(), d.z()); });
  expect_symmetry(g, g.mirror_yz, [](Eigen::Vector3d d) { return Eigen::Vector3d(-d.x(), d.y(), d.z()); });
}

TEST(LatLongGrid, ExactSolidAnglesAndSymmetries) {
  const auto g = icobrdf::build_lat_long_grid(6, 16, 3);
  EXPECT_NO_THROW(icobrdf::validate(g));
  EXPECT_NEAR(g.solid_angles.sum(), 2 * M_PI, kSumTol * 2 * M_PI);
  // The polar cap band: 2 pi (1 - cos(15 deg)) / 16 per cell.
  EXPECT_NEAR(g.solid_angles[0], 2 * M_PI * (1 - std::cos(M_PI / 12)) / 16, kSumTol);
  expect_symmetry(g, g.rotate_pi, [](Eigen::Vector3d d) { return icobrdf::mirror_direction(d); });
  expect_symmetry(g, g.mirror_xz, [](Eigen::Vector3d d) { return Eigen::Vector3d(d.x(), -d.y(), d.z()); });
  expect_symmetry(g, g.mirror_yz, [](Eigen::Vector3d d) { return Eigen::Vector3d(-d.x(), d.y(), d.z()); });
}

}  // namespace ICOBRDF_UNITY_ID
