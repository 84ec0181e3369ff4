// Grid <-> /grid round trips (exact: float64 stored, every member compared bit for bit) and refusal of
// inconsistent grid groups.
#include <gtest/gtest.h>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/grid_file.hpp"
#include "io_test_support.hpp"

#if __has_include("icobrdf/mesh/tessellation.hpp") && !defined(ICOBRDF_NO_TESSELLATION)
#include "icobrdf/mesh/tessellation.hpp"
#include "tests/support/unity_id.hpp"
#define ICOBRDF_HAVE_TESSELLATION 1
#endif

namespace ICOBRDF_UNITY_ID {

using icobrdf::Grid;

void expect_identical(const Grid& a, const Grid& b) {
  EXPECT_EQ(a.kind, b.kind);
  EXPECT_EQ(a.level, b.level);
  EXPECT_EQ(a.cubature_degree, b.cubature_degree);
  EXPECT_TRUE(a.directions == b.directions);
  EXPECT_TRUE(a.solid_angles == b.solid_angles);
  EXPECT_EQ(a.cubature_offsets, b.cubature_offsets);
  EXPECT_TRUE(a.cubature_points == b.cubature_points);
  EXPECT_TRUE(a.cubature_weights == b.cubature_weights);
  EXPECT_EQ(a.vertices.rows(), b.vertices.rows());
  EXPECT_TRUE(a.vertices == b.vertices);
  EXPECT_EQ(a.faces.rows(), b.faces.rows());
  EXPECT_TRUE(a.faces == b.faces);
  EXPECT_EQ(a.neighbours.rows(), b.neighbours.rows());
  EXPECT_TRUE(a.neighbours == b.neighbours);
  EXPECT_EQ(a.is_half, b.is_half);
  EXPECT_EQ(a.rotate_pi.size(), b.rotate_pi.size());
  EXPECT_TRUE(a.rotate_pi == b.rotate_pi);
  EXPECT_TRUE(a.mirror_xz == b.mirror_xz);
  EXPECT_TRUE(a.mirror_yz == b.mirror_yz);
}

Grid round_trip(const Grid& g, const std::string& path) {
  icobrdf::BankContents b;
  b.grid = g;
  icobrdf::write_bank(path, b);
  const auto r = icobrdf::read_bank(path);
  EXPECT_TRUE(r.grid.has_value());
  return r.grid ? *r.grid : Grid{};
}

TEST(GridFile, SyntheticGridRoundTripsExactly) {
  icobrdf::test::ScratchDir dir;
  const Grid g = icobrdf::test::synthetic_grid();
  ASSERT_NO_THROW(icobrdf::validate(g));
  const Grid r = round_trip(g, dir / "grid.h5");
  EXPECT_NO_THROW(icobrdf::validate(r));
  expect_identical(g, r);
}

TEST(GridFile, OptionalMembersAbsentStayEmpty) {
  icobrdf::test::ScratchDir dir;
  Grid g = icobrdf::test::synthetic_grid();
  g.vertices.resize(0, 3);
  g.faces.resize(0, 3);
  g.neighbours.resize(0, 3);
  g.is_half.clear();
  g.rotate_pi.resize(0);
  g.mirror_xz.resize(0);
  g.mirror_yz.resize(0);
  const Grid r = round_trip(g, dir / "grid.h5");
  expect_identical(g, r);
}

TEST(GridFile, InvalidGridIsAnArgumentErrorAndNoFile) {
  icobrdf::test::ScratchDir dir;
  Grid g = icobrdf::test::synthetic_grid();
  g.cubature_weights[0] *= 2.0;  // weights no longer sum to the solid angle
  icobrdf::BankContents b;
  b.grid = g;
  EXPECT_THROW(icobrdf::write_bank(dir / "grid.h5", b), icobrdf::ArgumentError);
  EXPECT_TRUE(dir.entries().empty());
}

#ifdef ICOBRDF_HAVE_TESSELLATION
TEST(GridFile, EqualAreaLevel2RoundTripsExactly) {
  icobrdf::test::ScratchDir dir;
  const Grid g = icobrdf::build_equal_area_grid(2);
  const Grid r = round_trip(g, dir / "grid.h5");
  // 10 * 4^2 + 2^3 cells (SPEC-NOTES, discrete engine).
  EXPECT_EQ(r.cells(), 168);
  expect_identical(g, r);
}
#endif
}  // namespace ICOBRDF_UNITY_ID
