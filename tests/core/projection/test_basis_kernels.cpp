// The batch kernels of the hemisphere basis against the one-direction evaluator hemisphere_basis_eval
// (whose accuracy test_hemisphere_basis.cpp and test_zernike.cpp establish against exact quadratures and
// 100-digit references): the block kernel, the weighted (cell) sums, the spectrum evaluation
// f = K(w_i)^T C K(w_r), and build_discrete_basis on grids whose cubature is exactly D2-equivariant (where
// only one cell per orbit is evaluated) against the same quantities computed cell by cell.
#include <gtest/gtest.h>
#include <omp.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "icobrdf/core/projection/discrete_basis.hpp"
#include "icobrdf/core/basis/grid_symmetry.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/grid/reference_grids.hpp"
#include "icobrdf/core/spectrum/spectrum_ops.hpp"
#include "tests/core/hard_directions.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

using namespace icobrdf;

// The kernels do the same operations as hemisphere_basis_eval in the same order; only the compiler's
// contraction of a * b + c into fused multiply-adds may differ, a few ulps of |K| <= sqrt((n + 1) / pi)
// (<= 6.4 at order 128) per recurrence step, over at most 128 steps: 1e-14 relative to the normalization.
constexpr double kKernelTol = 1e-14;
constexpr double kUnitRoundoff = 0x1p-53;
// Cell averages of the orbit path against the cell-by-cell sums: both are sums of ~30 weighted values
// of size <= sqrt((N + 1) / pi) in a different order, so they agree to ~30 ulps of that size.
constexpr double kAverageTol = 1e-13;
// G and its condition number from one cell per orbit against the full products: rounding of sums over
// thousands of cells, relative to max|G| ~ 1.
constexpr double kGramTol = 1e-12;
constexpr double kConditionTol = 1e-9;

RowMatrix3d test_directions(int count, unsigned seed) { return test::hard_directions(count, seed); }

std::vector<double> eval(int order, const Eigen::RowVector3d& d) {
  std::vector<double> v(static_cast<size_t>(hemisphere_basis_count(order)));
  hemisphere_basis_eval(order, d.transpose(), v.data());
  return v;
}

double norm_of(int j) { return std::sqrt((ansi_to_nl(j).n + 1) / M_PI); }

TEST(BasisBlock, EqualsTheOneDirectionEvaluatorIncludingPoleHorizonAndPadding) {
  for (int order : {0, 1, 8, 32, 128}) {
    const int m = hemisphere_basis_count(order);
    for (int n : {1, 3, 4, 31, 32, 33, 70}) {
      const RowMatrix3d d = test_directions(n, 11 + n);
      const int ld = n + 5;  // rows past n must stay untouched
      std::vector<double> out(static_cast<size_t>(ld) * m, -7.0);
      hemisphere_basis_block(order, n, d.data(), out.data(), ld);
      double worst = 0.0;
      for (int r = 0; r < n; ++r) {
        const auto k = eval(order, d.row(r));
        for (int j = 0; j < m; ++j)
          worst = std::max(worst, std::abs(out[static_cast<size_t>(j) * ld + r] - k[static_cast<size_t>(j)]) / norm_of(j));
      }
      EXPECT_LE(worst, kKernelTol) << "order " << order << ", " << n << " directions";
      for (int j = 0; j < m; ++j)
        for (int r = n; r < ld; ++r) ASSERT_EQ(out[static_cast<size_t>(j) * ld + r], -7.0) << "padding row written";
    }
  }
}

TEST(BasisBlock, WeightedSumEqualsTheSumOfSingleEvaluations) {
  for (int order : {0, 1, 8, 32, 128}) {
    const int m = hemisphere_basis_count(order);
    for (int n : {1, 5, 28, 33, 70}) {
      const RowMatrix3d d = test_directions(n, 5 + n);
      std::mt19937_64 rng(n);
      std::uniform_real_distribution<double> u(-1.0, 1.0);
      std::vector<double> w(static_cast<size_t>(n));
      for (auto& x : w) x = u(rng);
      std::vector<double> got(static_cast<size_t>(m)), sum(static_cast<size_t>(m), 0.0), mag(static_cast<size_t>(m), 0.0);
      hemisphere_basis_weighted_sum(order, n, d.data(), w.data(), got.data());
      for (int r = 0; r < n; ++r) {
        const auto k = eval(order, d.row(r));
        for (int j = 0; j < m; ++j) {
          sum[static_cast<size_t>(j)] += w[static_cast<size_t>(r)] * k[static_cast<size_t>(j)];
          mag[static_cast<size_t>(j)] += std::abs(w[static_cast<size_t>(r)]) * norm_of(j);
        }
      }
      // Each value to kKernelTol, then two sums of n terms in different orders: (n + 1) ulps of sum |w| |K|.
      for (int j = 0; j < m; ++j)
        ASSERT_NEAR(got[static_cast<size_t>(j)], sum[static_cast<size_t>(j)], (kKernelTol + 2 * (n + 1) * kUnitRoundoff) * mag[static_cast<size_t>(j)])
            << "order " << order << ", " << n << " points, mode " << j;
    }
  }
}

TEST(SpectrumEvaluation, EqualsTheBilinearFormOfSingleEvaluations) {
  // Orders 0..8 and 16 use all three register tiles (4, 5 or 6 columns of C) and a padded last panel;
  // 5000 pairs run on several threads and blocks, 1, 7 and 300 pairs exercise short blocks and tiles.
  for (int order : {0, 1, 2, 4, 6, 8, 16}) {
    const int m = hemisphere_basis_count(order);
    const Eigen::MatrixXd c = Eigen::MatrixXd::Random(m, m);
    for (int n : {1, 7, 300, 5000}) {
      const RowMatrix3d wi = test_directions(n, 3 + n), wr = test_directions(n, 1000 + n);
      const Eigen::VectorXd f = evaluate_coefficients(c, order, wi, wr);
      ASSERT_EQ(f.size(), n);
      for (int p = 0; p < n; p += (n > 300 ? 13 : 1)) {
        const auto ki = eval(order, wi.row(p)), kr = eval(order, wr.row(p));
        const Eigen::Map<const Eigen::VectorXd> a(ki.data(), m), b(kr.data(), m);
        const double expect = a.dot(c * b);
        // A sum of m^2 products: |error| <= 2 m u sum |a_i c_ij b_j| (plus the kernel's value error).
        const double terms = a.cwiseAbs().dot(c.cwiseAbs() * b.cwiseAbs());
        EXPECT_NEAR(f[p], expect, (4.0 * m * kUnitRoundoff + 2 * kKernelTol) * terms) << "order " << order << " pair " << p;
      }
    }
  }
}

// A copy of the grid whose cubature is exactly D2-equivariant: every cell that is not the smallest of its
// orbit receives the mapped points (in the same order) and weights of the orbit's smallest cell. Requires
// equal point counts and solid angles within an orbit, as on the lat-long grid.
Grid with_mapped_cubature(Grid g) {
  for (const auto& rep : d2_representatives(g)) {
    const int c = rep.cell;
    for (const auto& s : d2_maps(g)) {
      const int t = (*s.cells)[c];
      if (t == c) continue;
      const auto b = g.cubature_offsets[static_cast<size_t>(c)], e = g.cubature_offsets[static_cast<size_t>(c) + 1];
      const auto tb = g.cubature_offsets[static_cast<size_t>(t)];
      for (auto q = b; q < e; ++q) {
        g.cubature_points.row(tb + (q - b)) << s.sx * g.cubature_points(q, 0), s.sy * g.cubature_points(q, 1), g.cubature_points(q, 2);
        g.cubature_weights[tb + (q - b)] = g.cubature_weights[q];
      }
    }
  }
  return g;
}

// B row by row from single evaluations: B_cj = sum_q w_q K_j(x_q) / Omega_c.
Eigen::MatrixXd cell_averages(const Grid& g, int order) {
  const int m = hemisphere_basis_count(order);
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(g.cells(), m);
  for (int c = 0; c < g.cells(); ++c) {
    for (auto q = g.cubature_offsets[static_cast<size_t>(c)]; q < g.cubature_offsets[static_cast<size_t>(c) + 1]; ++q) {
      const auto k = eval(order, g.cubature_points.row(q));
      for (int j = 0; j < m; ++j) b(c, j) += g.cubature_weights[q] * k[static_cast<size_t>(j)];
    }
    b.row(c) /= g.solid_angles[c];
  }
  return b;
}

void expect_matches_cell_by_cell(const Grid& g, int order, int evaluated) {
  const auto d = build_discrete_basis(g, order);
  EXPECT_EQ(d.evaluated_cells, evaluated) << to_string(g.kind) << " order " << order;
  const Eigen::MatrixXd b = cell_averages(g, order);
  const double scale = std::sqrt((order + 1) / M_PI);
  EXPECT_LE((d.B - b).cwiseAbs().maxCoeff(), kAverageTol * scale) << to_string(g.kind) << " order " << order;
  const Eigen::MatrixXd gram = b.transpose() * g.solid_angles.asDiagonal() * b;
  EXPECT_LE((d.G - gram).cwiseAbs().maxCoeff(), kGramTol) << to_string(g.kind) << " order " << order;
  EXPECT_NEAR(d.gram_error, (gram - Eigen::MatrixXd::Identity(gram.rows(), gram.cols())).cwiseAbs().maxCoeff(), kGramTol);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(gram, Eigen::EigenvaluesOnly);
  const double cond = eig.eigenvalues().maxCoeff() / eig.eigenvalues().minCoeff();
  EXPECT_NEAR(d.condition, cond, kConditionTol * cond) << to_string(g.kind) << " order " << order;
}

TEST(DiscreteBasisOrbits, OneCellPerOrbitEqualsTheCellByCellBasis) {
  // Polar Gauss (nodes from cos and sin, so mirrored nodes agree only to rounding: mapped exactly here): one
  // point per cell, cells on the mirror axes are fixed by a mirror (their reversed modes must vanish).
  // Lat-long with mapped cubature: four cells per orbit, nine points per cell.
  // Orbits of the polar Gauss grid 12 x 40: nodes m = 0 and 20 (on the x axis) form orbits of 2 with each
  // other, as do m = 10 and 30 (y axis); the other 36 nodes of a ring form 9 orbits of 4: 11 per ring.
  expect_matches_cell_by_cell(with_mapped_cubature(build_polar_gauss_grid(12, 40)), 8, 12 * 11);
  // Unmapped, its mirrored nodes agree within rounding, far inside kMirroredCubatureRelTol: the same orbits.
  expect_matches_cell_by_cell(build_polar_gauss_grid(12, 40), 8, 12 * 11);
  const Grid mapped = with_mapped_cubature(build_lat_long_grid(12, 32, 3));
  for (int order : {0, 1, 8, 12}) expect_matches_cell_by_cell(mapped, order, mapped.cells() / 4);
  // The plain lat-long grid lists mirrored points in another order: the rule compares them as a set
  // (icobrdf/core/basis/grid_symmetry.hpp cubature_is_image), so it too goes by orbits, with the same results.
  expect_matches_cell_by_cell(build_lat_long_grid(12, 32, 3), 8, 12 * 32 / 4);
}

TEST(DiscreteBasisOrbits, AnInexactImageIsEvaluatedItself) {
  // Move one point of a non-representative cell by 1e-9: its row must be its own cell average (within
  // rounding), not the mirrored row of its representative (which now differs by ~1e-9 x |grad K|).
  Grid g = with_mapped_cubature(build_lat_long_grid(12, 32, 3));
  const int c = 0, t = g.rotate_pi[c];
  const auto q = g.cubature_offsets[static_cast<size_t>(t)];
  g.cubature_points(q, 0) += 1e-9;
  g.cubature_points.row(q).normalize();
  const int order = 8;
  const auto d = build_discrete_basis(g, order);
  EXPECT_EQ(d.evaluated_cells, g.cells());
  const Eigen::MatrixXd b = cell_averages(g, order);
  EXPECT_LE((d.B.row(t) - b.row(t)).cwiseAbs().maxCoeff(), kAverageTol * std::sqrt((order + 1) / M_PI));
  double moved = 0.0;
  for (int j = 0; j < d.modes(); ++j) moved = std::max(moved, std::abs(d.B(t, j) - std::pow(-1.0, ansi_to_nl(j).l) * d.B(c, j)));
  EXPECT_GT(moved, 1e-12);
}

TEST(DiscreteBasisOrbits, IdenticalOnOneAndTwoThreads) {
  const Grid g = with_mapped_cubature(build_lat_long_grid(12, 32, 3));
  omp_set_num_threads(1);
  const auto one = build_discrete_basis(g, 12);
  omp_set_num_threads(2);
  const auto two = build_discrete_basis(g, 12);
  EXPECT_EQ((one.B - two.B).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((one.G - two.G).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(one.condition, two.condition);
  EXPECT_EQ(one.evaluated_cells, g.cells() / 4);
}

TEST(BasisBlock, FirstInvalidDirectionIsTheFirstBadRowOnAnyNumberOfThreads) {
  // 300 000 rows (validated on several threads): bad rows at 150 000 (z below the slack) and 299 999 (NaN);
  // z = -1e-12 itself is on the horizon, and z = 2 (not a unit vector) is not this function's concern.
  RowMatrix3d d = RowMatrix3d::Zero(300000, 3);
  d.col(2).setOnes();
  d(10, 2) = -1e-12;
  d(20, 2) = 2.0;
  EXPECT_EQ(first_invalid_direction(d), -1);
  d(299999, 1) = std::nan("");
  d(150000, 2) = -2e-12;
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    EXPECT_EQ(first_invalid_direction(d), 150000);
    EXPECT_EQ(first_invalid_direction(d, 1e-11), 299999);  // a larger slack accepts row 150 000
  }
  d(7, 0) = std::numeric_limits<double>::infinity();
  EXPECT_EQ(first_invalid_direction(d), 7);
  EXPECT_EQ(first_invalid_direction(RowMatrix3d(0, 3)), -1);
}

}  // namespace ICOBRDF_UNITY_ID
