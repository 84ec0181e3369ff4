#include <gtest/gtest.h>

#include <cmath>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/grid/grid.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

// A two-cell grid: the upper hemisphere split into the half-spaces x >= 0 and x < 0, one cubature point
// per cell. Each cell subtends pi sr (a quarter sphere).
icobrdf::Grid two_cell_grid() {
  icobrdf::Grid g;
  g.kind = icobrdf::GridKind::Custom;
  g.directions.resize(2, 3);
  const double s = std::sqrt(0.5);
  g.directions << s, 0, s, -s, 0, s;
  g.solid_angles = Eigen::Vector2d(M_PI, M_PI);
  g.cubature_offsets = {0, 1, 2};
  g.cubature_points = g.directions;
  g.cubature_weights = g.solid_angles;
  g.rotate_pi = Eigen::Vector2i(1, 0);
  return g;
}

TEST(Grid, ValidGridPasses) { EXPECT_NO_THROW(icobrdf::validate(two_cell_grid())); }

TEST(Grid, RejectsWeightsThatDoNotSumToTheSolidAngle) {
  auto g = two_cell_grid();
  g.cubature_weights[1] *= 1.0 + 1e-9;
  EXPECT_THROW(icobrdf::validate(g), std::invalid_argument);
}

TEST(Grid, RejectsDirectionsBelowTheHorizon) {
  auto g = two_cell_grid();
  g.directions.row(0) << 0, 0, -1;
  EXPECT_THROW(icobrdf::validate(g), std::invalid_argument);
}

TEST(Grid, RejectsNonPermutationSymmetryMap) {
  auto g = two_cell_grid();
  g.rotate_pi = Eigen::Vector2i(0, 0);
  EXPECT_THROW(icobrdf::validate(g), std::invalid_argument);
}

}  // namespace ICOBRDF_UNITY_ID
