// DirectionSampler and CellDistribution (icobrdf/mesh/direction_sampler.hpp): the equal-area property the
// sampler relies on (finite-difference Jacobian of the inverse Snyder map), draws landing in their cell,
// the pdf integrating to 1 by an independent quadrature, chi-squared goodness of fit with bins finer than
// the cells (so uniformity inside cells is tested), and refusals.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <random>
#include <vector>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/mesh/direction_sampler.hpp"
#include "icobrdf/mesh/hemi_lattice.hpp"
#include "icobrdf/mesh/icosahedron.hpp"
#include "icobrdf/mesh/snyder_projection.hpp"
#include "icobrdf/mesh/tessellation.hpp"
#include "tests/support/chi_square.hpp"
#include "tests/support/unity_id.hpp"

using namespace icobrdf;

namespace ICOBRDF_UNITY_ID {

// Central differences with step h = 1e-6 in barycentric coordinates: rounding 1e-16 / h = 1e-10; truncation
// O(h^2 / r^2) grows towards the face centre (distance r), where the map's Cartesian derivatives are
// singular: measured 3e-9 at worst over these points (9e-8 with h = 1e-5, 6e-6 with h = 1e-4: the h^2
// law). 1e-8 is above that and far below any real area distortion (the gnomonic map's is 40 %).
constexpr double kFdStep = 1e-6;
constexpr double kJacobianTol = 1e-8;
// Significance of each chi-squared test (the 1e-3), Sidak-corrected over the tests of this file.
constexpr int kChiSquareTests = 3;
const double kSignificance = 1.0 - std::pow(1.0 - 1e-3, 1.0 / kChiSquareTests);
// The midpoint quadrature of a piecewise-constant density on a (cos theta, phi) grid errs only in the
// quadrature rectangles cut by cell edges. At level 2 and 1000 x 2000 rectangles, about 5e4 of 2e6 are cut;
// each errs by at most its own mass (5e-7 for a density within a factor 2 of uniform) with random signs:
// a standard deviation of about sqrt(5e4) * 5e-7 / 2 = 6e-5. 1e-3 is 15 of those.
constexpr double kQuadratureTol = 1e-3;
// The grid's cubature points are inside their cells, so summing p_k / A_k times the weights gives
// sum_k p_k = 1 up to rounding of 10^4 terms.
constexpr double kCubatureSumTol = 1e-12;

// Random masses in [1, 2) (a density within a factor 2 of uniform, every cell drawn).
Eigen::VectorXd random_masses(int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(1.0, 2.0);
  Eigen::VectorXd m(n);
  for (int k = 0; k < n; ++k) m[k] = u(rng);
  return m;
}

// The sampler's premise: the inverse Snyder map has Jacobian determinant 1 (planar area in sr = solid
// angle) everywhere off the sub-triangle boundaries, on every face. Parametrize the face by (a, b) ->
// l = (1 - a - b, a, b): the planar area element is 2 * kFaceArea da db, the solid-angle element
// |d_a x d_b| da db.
TEST(DirectionSampler, InverseSnyderMapIsEqualArea) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int checked = 0;
  double worst = 0;
  for (int f = 0; f < 12; ++f) {
    const SnyderProjection p(hemi_face_corners(f));
    for (int t = 0; t < 200; ++t) {
      double a = u(rng), b = u(rng);
      if (a + b > 1) a = 1 - a, b = 1 - b;
      const Eigen::Vector3d l(1 - a - b, a, b);
      // stay 10 steps away from the medians (where the derivative jumps) and the face's edges
      const double margin = 10 * kFdStep;
      if (std::abs(l[0] - l[1]) < margin || std::abs(l[1] - l[2]) < margin || std::abs(l[0] - l[2]) < margin ||
          l.minCoeff() < margin)
        continue;
      const Eigen::Vector3d ea(-1, 1, 0), eb(-1, 0, 1);
      const Eigen::Vector3d da = (p.inverse(l + kFdStep * ea) - p.inverse(l - kFdStep * ea)) / (2 * kFdStep);
      const Eigen::Vector3d db = (p.inverse(l + kFdStep * eb) - p.inverse(l - kFdStep * eb)) / (2 * kFdStep);
      const double ratio = da.cross(db).norm() / (2 * SnyderProjection::kFaceArea);
      worst = std::max(worst, std::abs(ratio - 1));
      ++checked;
    }
  }
  EXPECT_GT(checked, 2000);
  EXPECT_LT(worst, kJacobianTol);
}

// Every draw inside a cell lies in that cell (by the independent CellLocator), for all cells of level 3,
// including the 16 equator half cells and the central cells that straddle all 6 sub-triangles.
TEST(DirectionSampler, DrawsLandInTheirCell) {
  const DirectionSampler s(3);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int wrong = 0, below = 0;
  for (int c = 0; c < s.cells(); ++c)
    for (int t = 0; t < 50; ++t) {
      const Eigen::Vector3d d = s.uniform_in_cell(c, u(rng), u(rng));
      wrong += s.locator().locate(d) != c;
      below += d.z() < 0;
      ASSERT_NEAR(d.norm(), 1.0, 1e-14);
    }
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(below, 0);
}

// Uniform in solid angle inside a cell: the sample mean of the direction over a cell equals the cell average
// of the direction by the grid's own degree-9 cubature (an independent integration path: Stroud rule on the
// cell's pieces), within 5 standard errors (false failure probability 6e-7 per component), with the
// standard error from the cubature variance. Cells: an ordinary one, an equator half cell and a face's
// central cell (split by all 6 sub-triangle boundaries) at level 1 (large cells, large effects).
TEST(DirectionSampler, UniformInsideCells) {
  const DirectionSampler s(1);
  const Grid fine = build_equal_area_grid(1, 9);
  const HemiLattice lat(1);
  std::vector<int> picks;
  int half = -1, central = -1;
  for (int c = 0; c < lat.cells(); ++c) {
    if (lat.cell(c).half && half < 0) half = c;
    if (!lat.cell(c).half && lat.cell(c).down && central < 0) central = c;  // n = 2: the down triangle is central
  }
  picks = {0, half, central};
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  constexpr int kDraws = 200000;
  for (int c : picks) {
    ASSERT_GE(c, 0);
    Eigen::Vector3d mean_q = Eigen::Vector3d::Zero(), sq = Eigen::Vector3d::Zero();
    double wsum = 0;
    for (auto q = fine.cubature_offsets[c]; q < fine.cubature_offsets[c + 1]; ++q) {
      const Eigen::Vector3d x = fine.cubature_points.row(q).transpose();
      mean_q += fine.cubature_weights[q] * x;
      sq += fine.cubature_weights[q] * x.cwiseProduct(x);
      wsum += fine.cubature_weights[q];
    }
    mean_q /= wsum;
    const Eigen::Vector3d sd = (sq / wsum - mean_q.cwiseProduct(mean_q)).cwiseMax(0).cwiseSqrt();
    Eigen::Vector3d mean_s = Eigen::Vector3d::Zero();
    for (int t = 0; t < kDraws; ++t) mean_s += s.uniform_in_cell(c, u(rng), u(rng));
    mean_s /= kDraws;
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(mean_s[i], mean_q[i], 5 * sd[i] / std::sqrt(double(kDraws)) + 1e-15) << "cell " << c << " component " << i;
  }
}

TEST(DirectionSampler, PdfIntegratesToOne) {
  const DirectionSampler s(2);
  const CellDistribution dist(random_masses(s.cells(), 21), "test");
  // The grid's degree-9 cubature (points strictly inside cells).
  const Grid fine = build_equal_area_grid(2, 9);
  double cub = 0;
  for (Eigen::Index q = 0; q < fine.cubature_points.rows(); ++q)
    cub += fine.cubature_weights[q] * s.pdf(dist, Eigen::Vector3d(fine.cubature_points.row(q).transpose()));
  EXPECT_NEAR(cub, 1.0, kCubatureSumTol);
  // Independent: midpoint rule in (cos theta, phi).
  const int nz = 1000, nphi = 2000;
  const RowMatrix3d w = test_support::midpoint_directions(nz, nphi);
  const Eigen::VectorXd p = s.pdf(dist, w);  // the batch form (BatchPdfEqualsSingle: the same values)
  double total = 0;
  for (Eigen::Index i = 0; i < p.size(); ++i) total += p[i];
  total *= (1.0 / nz) * (2 * M_PI / nphi);
  EXPECT_NEAR(total, 1.0, kQuadratureTol);
}

// Chi-squared at level 2 (168 cells) with 30 x 60 bins (about 10 bins per cell): a density uniform per
// cell only in the planar preimage of a non-equal-area map, or a wrong cell choice, fails.
TEST(DirectionSampler, ChiSquaredAgainstPdf) {
  const DirectionSampler s(2);
  for (unsigned seed : {1u, 2u, 3u}) {
    const CellDistribution dist(random_masses(s.cells(), seed), "test");
    std::mt19937_64 rng(100 + seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<Eigen::Vector3d> draws;
    constexpr int kDraws = 400000;
    int mismatched = 0;
    for (int t = 0; t < kDraws; ++t) {
      const DirectionSample d = s.sample(dist, u(rng), u(rng));
      draws.push_back(d.direction);
      mismatched += d.pdf != s.pdf(dist, d.direction);
    }
    EXPECT_EQ(mismatched, 0);
    const auto r = test_support::chi_square_directions(draws, [&](const RowMatrix3d& w) { return s.pdf(dist, w); }, 30, 60, 8);
    EXPECT_NEAR(r.expected_total, 1.0, kQuadratureTol);
    EXPECT_GT(r.p_value, kSignificance) << "seed " << seed << ": chi2 " << r.chi2 << ", dof " << r.dof;
  }
}

TEST(CellDistribution, ZeroCellsAreNeverDrawnAndEndsAreSafe) {
  Eigen::VectorXd m(5);
  m << 0, 1, 0, 3, 0;
  const CellDistribution d(m, "test");
  double r = 0;
  EXPECT_EQ(d.sample(0.0, r), 1);
  EXPECT_EQ(r, 0.0);
  EXPECT_EQ(d.sample(0.25, r), 3);  // cdf: 0, 0, .25, .25, 1, 1
  EXPECT_EQ(r, 0.0);
  EXPECT_EQ(d.sample(1.0, r), 3);
  EXPECT_LT(r, 1.0);
  EXPECT_EQ(d.sample(0.125, r), 1);
  EXPECT_DOUBLE_EQ(r, 0.5);
  EXPECT_DOUBLE_EQ(d.probability(3), 0.75);
}

TEST(CellDistribution, RefusesAllZeroNegativeAndNonFinite) {
  EXPECT_THROW(CellDistribution(Eigen::VectorXd::Zero(4), "row"), ArgumentError);
  Eigen::VectorXd m = Eigen::VectorXd::Ones(4);
  m[2] = -1;
  EXPECT_THROW(CellDistribution(m, "row"), ArgumentError);
  m[2] = std::nan("");
  EXPECT_THROW(CellDistribution(m, "row"), ArgumentError);
  m[2] = INFINITY;
  EXPECT_THROW(CellDistribution(m, "row"), ArgumentError);
  try {
    CellDistribution(Eigen::VectorXd::Zero(4), "row of w_i");
    FAIL();
  } catch (const ArgumentError& e) {
    EXPECT_EQ(std::string(e.what()), "row of w_i: every one of the 4 cells has mass 0, nothing to sample");
  }
  const DirectionSampler s(0);
  EXPECT_THROW(s.sample(CellDistribution(Eigen::VectorXd::Ones(3), "x"), 0.5, 0.5), ArgumentError);
}

// The batch pdf (CellLocator's block lookup) gives the single-direction values, 0 below the horizon.
TEST(DirectionSampler, BatchPdfEqualsSingle) {
  const DirectionSampler s(4);
  const CellDistribution dist(random_masses(s.cells(), 9), "test");
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  RowMatrix3d w(1000, 3);
  for (int i = 0; i < 1000; ++i) {
    Eigen::Vector3d d(u(rng), u(rng), u(rng));
    w.row(i) = d.normalized().transpose();  // half of them below the horizon
  }
  const Eigen::VectorXd batch = s.pdf(dist, w);
  int below = 0;
  for (int i = 0; i < 1000; ++i) {
    EXPECT_EQ(batch[i], s.pdf(dist, Eigen::Vector3d(w.row(i).transpose()))) << i;
    if (w(i, 2) < 0) {
      EXPECT_EQ(batch[i], 0.0);
      ++below;
    }
  }
  EXPECT_GT(below, 400);
}

}  // namespace ICOBRDF_UNITY_ID
