// ParameterGrid, BilinearSlices and MarginalWarp2D (icobrdf/core/tables/parameter_grid.hpp, icobrdf/core/tables/bilinear_slices.hpp,
// icobrdf/core/tables/marginal_warp.hpp). Expected values are derived by hand: a constant density warps by the identity,
// a density a + b x by x -> (a x + b x^2 / 2) / (a + b / 2) (its CDF), and blends are linear in the parameters.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "icobrdf/core/tables/bilinear_slices.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/tables/marginal_warp.hpp"
#include "icobrdf/core/tables/parameter_grid.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

// Double rounding of a few dozen operations on values of order 1.
constexpr double kTol = 1e-13;

// h x w table of a + b x + c y at the nodes (x = k / (w - 1), y = j / (h - 1)).
std::vector<double> affine_table(int w, int h, double a, double b, double c) {
  std::vector<double> v;
  for (int j = 0; j < h; ++j)
    for (int k = 0; k < w; ++k) v.push_back(a + b * k / (w - 1.0) + c * j / (h - 1.0));
  return v;
}

double linear_cdf(double x, double a, double b) { return (a * x + b * x * x / 2) / (a + b / 2); }

TEST(ParameterGrid, WeightsAtBetweenAndBeyondNodes) {
  const ParameterGrid g({{0.0, 1.0, 3.0}});
  const double mid = 2.0, below = -1.0, above = 7.0, at = 1.0;
  SliceBlend b = g.blend(&mid);  // halfway between nodes 1 and 2
  ASSERT_EQ(b.count, 2);
  EXPECT_EQ(b.slice[0], 1);
  EXPECT_EQ(b.slice[1], 2);
  EXPECT_NEAR(b.weight[0], 0.5, kTol);
  EXPECT_NEAR(b.weight[1], 0.5, kTol);
  b = g.blend(&below);  // held at the first node
  EXPECT_EQ(b.slice[0], 0);
  EXPECT_NEAR(b.weight[0], 1.0, kTol);
  EXPECT_NEAR(b.weight[1], 0.0, kTol);
  b = g.blend(&above);  // held at the last node
  EXPECT_EQ(b.slice[1], 2);
  EXPECT_NEAR(b.weight[1], 1.0, kTol);
  b = g.blend(&at);
  double total = 0, value = 0;
  for (int c = 0; c < b.count; ++c) total += b.weight[c], value += b.weight[c] * b.slice[c];
  EXPECT_NEAR(total, 1.0, kTol);
  EXPECT_NEAR(value, 1.0, kTol);  // exactly node 1
}

TEST(ParameterGrid, ProductOfAxesFirstAxisSlowest) {
  // Axes of 2, 1 and 3 nodes: strides 3, 0 (single node), 1; 6 slices.
  const ParameterGrid g({{0.0, 1.0}, {5.0}, {0.0, 1.0, 2.0}});
  EXPECT_EQ(g.slices(), 6);
  const double p[3] = {0.25, 99.0, 1.5};
  const SliceBlend b = g.blend(p);
  ASSERT_EQ(b.count, 4);
  // Expected: axis 0 (0, 0.75), (1, 0.25); axis 2 (1, 0.5), (2, 0.5).
  double w[6] = {0, 0, 0, 0, 0, 0};
  for (int c = 0; c < b.count; ++c) w[b.slice[c]] += b.weight[c];
  EXPECT_NEAR(w[0 * 3 + 1], 0.375, kTol);
  EXPECT_NEAR(w[0 * 3 + 2], 0.375, kTol);
  EXPECT_NEAR(w[1 * 3 + 1], 0.125, kTol);
  EXPECT_NEAR(w[1 * 3 + 2], 0.125, kTol);
}

TEST(ParameterGrid, RefusesBadAxes) {
  EXPECT_THROW(ParameterGrid({{1.0, 1.0}}), ArgumentError);
  EXPECT_THROW(ParameterGrid(std::vector<std::vector<double>>{std::vector<double>{}}), ArgumentError);
  EXPECT_THROW(ParameterGrid({{0.0}, {0.0}, {0.0}, {0.0}}), ArgumentError);
  EXPECT_THROW(ParameterGrid({{0.0, NAN}}), ArgumentError);
}

TEST(BilinearSlices, ReproducesAffineFunctionsAndBlends) {
  // Slice 0: 1 + 2x + 3y, slice 1: 5 - x; a bilinear interpolant is exact for both.
  std::vector<double> v = affine_table(4, 3, 1, 2, 3), s1 = affine_table(4, 3, 5, -1, 0);
  v.insert(v.end(), s1.begin(), s1.end());
  const BilinearSlices t(v, 4, 3, ParameterGrid({{10.0, 20.0}}));
  const double p0 = 10.0, p = 12.5;  // weights 0.75 / 0.25
  for (double x : {0.0, 0.13, 0.5, 0.99, 1.0})
    for (double y : {0.0, 0.4, 1.0}) {
      EXPECT_NEAR(t.eval(x, y, &p0), 1 + 2 * x + 3 * y, kTol);
      EXPECT_NEAR(t.eval(x, y, &p), 0.75 * (1 + 2 * x + 3 * y) + 0.25 * (5 - x), kTol);
    }
  EXPECT_NEAR(t.eval(-3.0, 2.0, &p0), 1 + 3, kTol);  // clamped to (0, 1)
}

TEST(BilinearSlices, PositiveNodesOfVeryDifferentSizeStayPositiveAndExactAtNodes) {
  // Nodes 0.5 and 4e31 in one row (the table fuzz_rgl_bsdf found): at y = 1 the value is the second row's
  // interpolant, 0.5 + 0.0015 (1 - x) exactly up to rounding, not the 0 that a + (b - a) t cancels to.
  const BilinearSlices t({0.5, 4e31, 0.5015, 0.5}, 2, 2, ParameterGrid());
  for (double x : {0.0, 0.3, 0.64005119279497236, 1.0}) {
    const double v = t.eval(x, 1.0, nullptr);
    EXPECT_GT(v, 0.0) << x;
    EXPECT_NEAR(v, 0.5015 + (0.5 - 0.5015) * x, kTol) << x;
  }
  EXPECT_EQ(t.eval(1.0, 0.0, nullptr), 4e31);  // exact at a node
  for (double y : {1e-17, 0.25, 1 - 1e-16}) EXPECT_GT(t.eval(0.9, y, nullptr), 0.0) << y;
}

TEST(MarginalWarp2D, DensityOfVeryDifferentSizeInvertsInsideTheSquare) {
  // A row of density 1e-30 next to one of 1e30: every inverse stays in [0, 1]^2 and is finite.
  const MarginalWarp2D w({1e-30, 1e-30, 1e-30, 1e30, 3.0, 1e30}, 3, 2, ParameterGrid());
  const SliceBlend b = w.grid().blend(nullptr);
  for (double x : {0.0, 1e-17, 0.5, 1 - 1e-16, 1.0})
    for (double y : {0.0, 1e-17, 0.5, 1 - 1e-16, 1.0}) {
      const Eigen::Vector2d s = w.invert(x, y, b);
      EXPECT_TRUE(s.allFinite());
      EXPECT_GE(s.minCoeff(), 0.0);
      EXPECT_LE(s.maxCoeff(), 1.0 + kTol);
      EXPECT_GE(w.density(x, y, b), 0.0);
    }
}

TEST(MarginalWarp2D, ConstantDensityIsTheIdentity) {
  const MarginalWarp2D w(std::vector<double>(5 * 4, 2.5), 5, 4, ParameterGrid());
  const SliceBlend b = w.grid().blend(nullptr);
  for (double x : {0.0, 0.1, 0.37, 0.5, 0.93, 1.0})
    for (double y : {0.0, 0.2, 0.66, 1.0}) {
      const Eigen::Vector2d s = w.invert(x, y, b);
      EXPECT_NEAR(s.x(), x, kTol);
      EXPECT_NEAR(s.y(), y, kTol);
      EXPECT_NEAR(w.density(x, y, b), 1.0, kTol);  // normalized
    }
}

TEST(MarginalWarp2D, LinearDensityInvertsToItsCdf) {
  const double a = 0.5, b = 3.0;
  const MarginalWarp2D w(affine_table(6, 3, a, b, 0), 6, 3, ParameterGrid());
  const SliceBlend bl = w.grid().blend(nullptr);
  for (double x : {0.0, 0.05, 0.3, 0.5, 0.77, 1.0})
    for (double y : {0.0, 0.45, 1.0}) {
      const Eigen::Vector2d s = w.invert(x, y, bl);
      EXPECT_NEAR(s.x(), linear_cdf(x, a, b), kTol) << x;
      EXPECT_NEAR(s.y(), y, kTol);  // every row has the same total: the marginal is uniform
      EXPECT_NEAR(w.density(x, y, bl), (a + b * x) / (a + b / 2), kTol);
    }
  // Along y: density 1 + 4y gives the marginal CDF (y + 2 y^2) / 3.
  const MarginalWarp2D wy(affine_table(3, 5, 1, 0, 4), 3, 5, ParameterGrid());
  for (double y : {0.1, 0.5, 0.9}) EXPECT_NEAR(wy.invert(0.3, y, bl).y(), linear_cdf(y, 1, 4), kTol);
}

TEST(MarginalWarp2D, BlendsNormalizedSlices) {
  // Slice 0: 2 (1 + 3x) (normalized: (1 + 3x) / 2.5), slice 1: constant 7 (identity): at the midpoint the
  // CDFs are averaged, not the raw densities.
  std::vector<double> v = affine_table(5, 2, 2, 6, 0), c(10, 7.0);
  v.insert(v.end(), c.begin(), c.end());
  const MarginalWarp2D w(v, 5, 2, ParameterGrid({{0.0, 1.0}}));
  const double p = 0.5;
  const SliceBlend b = w.grid().blend(&p);
  for (double x : {0.2, 0.6, 0.9}) EXPECT_NEAR(w.invert(x, 0.3, b).x(), 0.5 * linear_cdf(x, 1, 3) + 0.5 * x, kTol);
}

TEST(MarginalWarp2D, RefusesNegativeAndEmptySlices) {
  std::vector<double> v(8, 1.0);
  v[3] = -0.5;
  EXPECT_THROW(MarginalWarp2D(v, 4, 2, ParameterGrid()), ArgumentError);
  EXPECT_THROW(MarginalWarp2D(std::vector<double>(8, 0.0), 4, 2, ParameterGrid()), ArgumentError);
  EXPECT_THROW(MarginalWarp2D(std::vector<double>(7, 1.0), 4, 2, ParameterGrid()), ArgumentError);
  EXPECT_THROW(MarginalWarp2D(std::vector<double>(4, 1.0), 4, 1, ParameterGrid()), ArgumentError);
}

}  // namespace
}  // namespace icobrdf
