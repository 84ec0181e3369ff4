// Geometry of the oriented icosahedron: unit vertices, 20 counter-clockwise faces, the hemisphere split
// into 8 whole and 4 bisected faces, and the mirror planes z = 0, x = 0, y = 0.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <map>
#include <utility>

#include "icobrdf/mesh/icosahedron.hpp"
#include "tests/support/unity_id.hpp"

using namespace icobrdf;

namespace ICOBRDF_UNITY_ID {
// Vertices are normalized doubles: 1e-14 is far above their rounding and far below any geometric error.
constexpr double kTol = 1e-14;

bool contains(const std::vector<Eigen::Vector3d>& set, const Eigen::Vector3d& p) {
  for (const auto& q : set)
    if ((q - p).norm() < kTol) return true;
  return false;
}

TEST(Icosahedron, TwelveUnitVerticesTwentyCcwFacesThirtyEdges) {
  const auto& v = icosahedron_vertices();
  ASSERT_EQ(v.size(), 12u);
  for (const auto& p : v) EXPECT_NEAR(p.norm(), 1.0, kTol);
  const auto& f = icosahedron_faces();
  ASSERT_EQ(f.size(), 20u);
  std::map<std::pair<int, int>, int> edge_use;
  for (const auto& t : f) {
    const double orient = (v[t[1]] - v[t[0]]).cross(v[t[2]] - v[t[0]]).dot(v[t[0]]);
    EXPECT_GT(orient, 0.0);
    for (int k = 0; k < 3; ++k) ++edge_use[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
  }
  EXPECT_EQ(edge_use.size(), 30u);  // Euler: V - E + F = 12 - 30 + 20 = 2
  for (const auto& [e, n] : edge_use) EXPECT_EQ(n, 2);
}

TEST(Icosahedron, MirrorPlanesAndTwoFoldAxis) {
  const auto& v = icosahedron_vertices();
  for (const auto& p : v) {
    EXPECT_TRUE(contains(v, Eigen::Vector3d(p.x(), p.y(), -p.z())));
    EXPECT_TRUE(contains(v, Eigen::Vector3d(-p.x(), p.y(), p.z())));
    EXPECT_TRUE(contains(v, Eigen::Vector3d(p.x(), -p.y(), p.z())));
    EXPECT_TRUE(contains(v, Eigen::Vector3d(-p.x(), -p.y(), p.z())));
  }
  // The pole is the midpoint of the edge (0, +-1, phi): a 2-fold axis.
  const Eigen::Vector3d mid = (v[0] + v[2]).normalized();
  EXPECT_NEAR((mid - Eigen::Vector3d(0, 0, 1)).norm(), 0.0, kTol);
}

TEST(Icosahedron, HemisphereHasEightWholeAndFourBisectedFaces) {
  const auto& v = icosahedron_vertices();
  const auto& h = hemi_icosahedron_faces();
  ASSERT_EQ(h.size(), 12u);
  int whole = 0, bis = 0;
  for (const auto& f : h) {
    const double orient = (v[f.v[1]] - v[f.v[0]]).cross(v[f.v[2]] - v[f.v[0]]).dot(v[f.v[0]]);
    EXPECT_GT(orient, 0.0);
    if (f.bisected) {
      ++bis;
      // Corner 0 on the equator, the other two mirror images under z -> -z; the median from corner 0
      // passes through the face centre, which is on the equator too.
      EXPECT_NEAR(v[f.v[0]].z(), 0.0, kTol);
      EXPECT_NEAR(v[f.v[1]].z(), -v[f.v[2]].z(), kTol);
      EXPECT_NEAR(f.centre.z(), 0.0, kTol);
      EXPECT_GT(v[f.v[f.upper_corner]].z(), 0.0);
    } else {
      ++whole;
      for (int k = 0; k < 3; ++k) EXPECT_GT(v[f.v[k]].z(), -kTol);
      EXPECT_GT(f.centre.z(), 0.0);
    }
  }
  EXPECT_EQ(whole, 8);
  EXPECT_EQ(bis, 4);
}

}  // namespace ICOBRDF_UNITY_ID
