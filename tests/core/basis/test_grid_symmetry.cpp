// cubature_is_image (icobrdf/core/basis/grid_symmetry.hpp) on a grid core builds itself, the lat-long grid with several
// points per cell: its mirrors send a cell's points onto its image's in another order, so the rule must
// compare them as a set. The hemi-icosahedral grids are checked in tests/mesh/test_mirrored_cubature.cpp.
#include <gtest/gtest.h>

#include <algorithm>

#include "icobrdf/core/basis/grid_symmetry.hpp"
#include "icobrdf/core/grid/reference_grids.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

TEST(GridSymmetryRule, LatLongGridPassesForEachMapInAnyOrder) {
  Grid g = build_lat_long_grid(4, 8, 3);
  ASSERT_TRUE(has_d2_maps(g));
  for (const auto& s : d2_maps(g))
    for (int c = 0; c < g.cells(); ++c) EXPECT_TRUE(cubature_is_image(g, s, c, (*s.cells)[c])) << "cell " << c;
  // Rotate the order of cell 0's points and weights: still the same set.
  const auto b = g.cubature_offsets[0], n = g.cubature_offsets[1] - b;
  ASSERT_GE(n, 2);
  RowMatrix3d p = g.cubature_points.middleRows(b, n);
  Eigen::VectorXd w = g.cubature_weights.segment(b, n);
  for (Eigen::Index k = 0; k < n; ++k) {
    g.cubature_points.row(b + k) = p.row((k + 1) % n);
    g.cubature_weights[b + k] = w[(k + 1) % n];
  }
  EXPECT_TRUE(sampling_is_d2_symmetric(g));
  EXPECT_TRUE(sampling_is_d2_symmetric(g, true));
}

TEST(GridSymmetryRule, OnePointOrWeightOffBy1e9Fails) {
  const Grid base = build_lat_long_grid(4, 8, 3);
  const D2Map s = d2_maps(base)[0];  // rotation by pi: never a fixed cell
  const int t = base.rotate_pi[0];
  Grid moved = base;
  moved.cubature_points(0, 0) += 1e-9;
  EXPECT_FALSE(cubature_is_image(moved, s, 0, t));
  EXPECT_FALSE(sampling_is_d2_symmetric(moved));
  Grid weighed = base;
  weighed.cubature_weights[0] *= 1.0 + 1e-9;
  EXPECT_FALSE(cubature_is_image(weighed, s, 0, t));
  EXPECT_FALSE(cubature_is_image(base, s, 0, base.cells()));  // not a cell
}

}  // namespace
}  // namespace icobrdf
