// The rule "a cell's mirrored cubature is the image of its own" (icobrdf/core/basis/grid_symmetry.hpp cubature_is_image),
// derived on the hemi-icosahedral grids (which is why it lives with the mesh tests: core's tests link
// core only). A grid built symmetric passes for each of the three D2 maps; moving one point or one weight by
// 1e-9 fails; reordering a cell's points passes (the cell average does not depend on the order).
#include <gtest/gtest.h>

#include <utility>

#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/core/basis/grid_symmetry.hpp"
#include "icobrdf/mesh/tessellation.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

// Every cell's image under map s carries the image of its sampling.
bool every_cell_maps(const Grid& g, const D2Map& s, bool centres = false) {
  for (int c = 0; c < g.cells(); ++c)
    if (!cubature_is_image(g, s, c, (*s.cells)[c], centres)) return false;
  return true;
}

// A cell whose image under mirror_yz is another cell, with at least two cubature points.
int moved_cell(const Grid& g) {
  for (int c = 0; c < g.cells(); ++c)
    if (g.mirror_yz[c] != c && g.cubature_offsets[c + 1] - g.cubature_offsets[c] >= 2) return c;
  return -1;
}

TEST(MirroredCubature, SymmetricGridsPassForEachMap) {
  for (const Grid& g : {build_equal_area_grid(2), build_fitting_grid(3, GridKind::EqualArea, false),
                        build_fitting_grid(3, GridKind::EqualArea, true), build_geodesic_grid(2)}) {
    ASSERT_TRUE(has_d2_maps(g));
    for (const auto& s : d2_maps(g)) {
      EXPECT_TRUE(every_cell_maps(g, s)) << to_string(g.kind) << " level " << g.level << " degree " << g.cubature_degree;
      EXPECT_TRUE(every_cell_maps(g, s, true)) << "centres, " << to_string(g.kind);
    }
    EXPECT_TRUE(sampling_is_d2_symmetric(g));
    EXPECT_TRUE(sampling_is_d2_symmetric(g, true));
  }
}

TEST(MirroredCubature, MovingOnePointOrWeightBy1e9Fails) {
  const Grid base = build_equal_area_grid(2);
  const int c = moved_cell(base);
  ASSERT_GE(c, 0);
  const D2Map s = d2_maps(base)[2];  // mirror_yz
  const int t = base.mirror_yz[c];
  ASSERT_TRUE(cubature_is_image(base, s, c, t));
  const auto p = base.cubature_offsets[c];
  for (int k = 0; k < 3; ++k) {
    Grid g = base;
    g.cubature_points(p, k) += 1e-9;
    EXPECT_FALSE(cubature_is_image(g, s, c, t)) << "coordinate " << k;
    EXPECT_FALSE(sampling_is_d2_symmetric(g));
  }
  Grid w = base;
  w.cubature_weights[p] *= 1.0 + 1e-9;
  EXPECT_FALSE(cubature_is_image(w, s, c, t));
  Grid a = base;
  a.solid_angles[t] *= 1.0 + 1e-9;
  EXPECT_FALSE(cubature_is_image(a, s, c, t));
  Grid d = base;
  d.directions(t, 0) += 1e-9;
  EXPECT_FALSE(cubature_is_image(d, s, c, t, true));
  EXPECT_TRUE(cubature_is_image(d, s, c, t));  // the cubature itself is untouched
}

TEST(MirroredCubature, PermutedOrderStillPasses) {
  Grid g = build_equal_area_grid(2);
  // Reverse every cell's points (with their weights): each image is now in a different order.
  for (int c = 0; c < g.cells(); ++c) {
    auto b = g.cubature_offsets[c], e = g.cubature_offsets[c + 1] - 1;
    for (; b < e; ++b, --e) {
      g.cubature_points.row(b).swap(g.cubature_points.row(e));
      std::swap(g.cubature_weights[b], g.cubature_weights[e]);
    }
  }
  // Only the cells with the mirrored image get the reversed order: undo it for every second orbit member.
  Grid h = build_equal_area_grid(2);
  for (int c = 0; c < h.cells(); ++c)
    if (h.mirror_yz[c] > c) {
      const auto b = h.cubature_offsets[c], n = h.cubature_offsets[c + 1] - b;
      h.cubature_points.middleRows(b, n) = g.cubature_points.middleRows(b, n);
      h.cubature_weights.segment(b, n) = g.cubature_weights.segment(b, n);
    }
  for (const Grid* x : {&g, &h}) {
    for (const auto& s : d2_maps(*x)) EXPECT_TRUE(every_cell_maps(*x, s));
    EXPECT_TRUE(sampling_is_d2_symmetric(*x));
  }
}

}  // namespace
}  // namespace icobrdf
