// The fast paths of model projection: vectorized GGX evaluation (MicrofacetModel::eval), LUT rows for a
// list of cells (sample_lut_rows), and the D2-symmetric streaming projection of isotropic models. Each is
// checked against the plain path it replaces.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <random>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/projection/discrete_basis.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/grid_symmetry.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/projection/lut.hpp"
#include "icobrdf/core/models/microfacet.hpp"
#include "icobrdf/core/projection/projection.hpp"
#include "icobrdf/core/grid/reference_grids.hpp"
#include "icobrdf/core/projection/streaming_projection.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

// Batch and pair-by-pair GGX use the same formulas with the divisions folded differently: a few ulps.
constexpr double kReorderTol = 1e-13;
// Symmetric and plain projections add the same products in another order (and the symmetric path
// replaces entries that vanish by symmetry, ~1e-17 in the plain path, by exact zeros).
constexpr double kAlgebraTol = 1e-12;

RowMatrix3d random_dirs(std::mt19937_64& rng, int n) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  RowMatrix3d d(n, 3);
  for (int k = 0; k < n; ++k) {
    const double z = u(rng), s = std::sqrt(1.0 - z * z), p = 2.0 * M_PI * u(rng);
    d.row(k) << s * std::cos(p), s * std::sin(p), z;
  }
  return d;
}

MicrofacetParams ggx(double ax, double ay, double azimuth, FresnelMode fresnel, SmithMasking masking) {
  MicrofacetParams p;
  p.anisotropic = ax != ay;
  p.alpha_x = ax;
  p.alpha_y = ay;
  p.azimuth_deg = azimuth;
  p.fresnel = fresnel;
  p.masking = masking;
  return p;
}

TEST(GgxBatch, EqualsPairByPairIncludingHardCases) {
  std::mt19937_64 rng(3);
  const int random_pairs = 1000;
  RowMatrix3d wi = random_dirs(rng, random_pairs), wr = random_dirs(rng, random_pairs);
  // Hard cases appended: normal incidence both ways, grazing pairs, double grazing, a point within the
  // horizon slack, one below the horizon, opposite horizontal directions (no half vector).
  const double sq = std::sqrt(0.5);
  const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> hard = {
      {{0, 0, 1}, {0, 0, 1}},   {{1, 0, 0}, {0, 0, 1}},     {{1, 0, 0}, {0, 1, 0}},    {{1, 0, 0}, {1, 0, 0}},
      {{sq, 0, sq}, {-sq, 0, sq}}, {{1, 0, -1e-13}, {0, 0, 1}}, {{0, 0.6, -0.8}, {0, 0, 1}}, {{1, 0, 0}, {-1, 0, 0}}};
  const int n = random_pairs + static_cast<int>(hard.size());
  wi.conservativeResize(n, 3);
  wr.conservativeResize(n, 3);
  for (size_t k = 0; k < hard.size(); ++k) {
    wi.row(random_pairs + static_cast<int>(k)) = hard[k].first.transpose();
    wr.row(random_pairs + static_cast<int>(k)) = hard[k].second.transpose();
  }
  for (const auto& p : {ggx(0.3, 0.3, 0, FresnelMode::Schlick, SmithMasking::HeightCorrelated),
                        ggx(0.05, 0.05, 0, FresnelMode::Dielectric, SmithMasking::Separable),
                        ggx(0.5, 0.1, 30, FresnelMode::None, SmithMasking::HeightCorrelated)}) {
    const MicrofacetModel m(p);
    Eigen::MatrixXd batch(n, 1);
    m.eval(wi, wr, batch);
    for (int k = 0; k < n; ++k) {
      // Reference: value() with the horizon rule of ScalarBrdfModel::eval (icobrdf/core/models/brdf_model.hpp).
      Eigen::Vector3d a = wi.row(k).transpose(), b = wr.row(k).transpose();
      double one = 0.0;
      if (a.z() >= -kHorizonSlack && b.z() >= -kHorizonSlack) {
        a.z() = std::max(a.z(), 0.0);
        b.z() = std::max(b.z(), 0.0);
        one = m.value(a, b);
      }
      EXPECT_NEAR(batch(k, 0), one, kReorderTol * std::max(1.0, std::abs(one))) << m.spec() << " pair " << k;
    }
    EXPECT_EQ(batch(n - 1, 0), 0.0) << "opposite horizontal directions";
    EXPECT_EQ(batch(n - 2, 0), 0.0) << "below the horizon";
  }
}

TEST(LutRows, ListOfCellsGivesTheSameRowsAsTheRange) {
  const Grid g = build_lat_long_grid(4, 8, 2);
  const MicrofacetModel m(ggx(0.3, 0.3, 0, FresnelMode::Schlick, SmithMasking::HeightCorrelated));
  std::vector<Eigen::MatrixXd> range, list;
  sample_lut_rows(m, g, true, LutSampling::CellAverage, 0, 10, range);
  sample_lut_rows(m, g, true, LutSampling::CellAverage, std::vector<int>{7, 0, 3}, list);
  ASSERT_EQ(list[0].rows(), 3);
  EXPECT_EQ((list[0].row(0) - range[0].row(7)).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((list[0].row(1) - range[0].row(0)).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((list[0].row(2) - range[0].row(3)).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_THROW(sample_lut_rows(m, g, true, LutSampling::CellAverage, std::vector<int>{g.cells()}, list), ArgumentError);
}

// The lat-long grid with an even number of sectors is D2-symmetric (icobrdf/core/grid/reference_grids.hpp). Equality
// of every streaming path with the materialized LUT, on 1 and 2 threads, is checked in
// test_streaming_reciprocity.cpp; here the structure the symmetric path imposes.
TEST(StreamingProjection, SymmetricPathKeepsOnlySymmetryAllowedCouplings) {
  const Grid g = build_lat_long_grid(6, 12, 2);
  const int order = 4;
  const auto p = make_projection(build_discrete_basis(g, order));
  // Isotropic: C couples only modes with the same signs under the rotation by pi and the mirrors, i.e.
  // the same parity of l and the same sign of l (l = 0 counting as positive); K_1^1 and K_1^-1 do not mix.
  const MicrofacetModel iso(ggx(0.3, 0.3, 0, FresnelMode::Schlick, SmithMasking::HeightCorrelated));
  const auto c = streaming_projection(iso, g, p, false);
  EXPECT_EQ(c[0](ansi_index(1, 1), ansi_index(1, -1)), 0.0);
  EXPECT_EQ(c[0](ansi_index(0, 0), ansi_index(1, 1)), 0.0);
  EXPECT_NE(c[0](ansi_index(0, 0), ansi_index(2, 0)), 0.0);
}

// K_j at a mapped direction is sign_j K_j (eq. 5 with phi -> phi + pi, -phi, pi - phi), so the signs of
// D2Map must reproduce the basis itself at random directions; the lane-parallel evaluator must equal the
// one-direction evaluator at hard directions (pole, equator, within the horizon slack) and random ones.
TEST(GridSymmetry, SignsMatchTheBasisAndLanesMatchOneByOne) {
  const int order = 12, m = hemisphere_basis_count(order);
  const Grid g = build_lat_long_grid(4, 8, 2);
  ASSERT_TRUE(has_d2_maps(g));
  std::mt19937_64 rng(9);
  const RowMatrix3d dirs = random_dirs(rng, 20);
  std::vector<double> k(static_cast<size_t>(m)), km(static_cast<size_t>(m));
  for (const auto& s : d2_maps(g))
    for (int r = 0; r < dirs.rows(); ++r) {
      const Eigen::Vector3d d = dirs.row(r).transpose();
      hemisphere_basis_eval(order, d, k.data());
      hemisphere_basis_eval(order, Eigen::Vector3d(s.sx * d.x(), s.sy * d.y(), d.z()), km.data());
      for (int j = 0; j < m; ++j) EXPECT_NEAR(km[static_cast<size_t>(j)], s.sign(ansi_to_nl(j).l) * k[static_cast<size_t>(j)], kReorderTol * 10);
    }
  // Classes: the sign pattern of a mode under the three maps identifies its class.
  for (int a = 0; a < m; ++a)
    for (int b = 0; b < m; ++b) {
      bool same = true;
      for (const auto& s : d2_maps(g)) same = same && s.sign(ansi_to_nl(a).l) == s.sign(ansi_to_nl(b).l);
      EXPECT_EQ(same, d2_class(a) == d2_class(b));
    }
  // Lanes against one by one.
  const double x[kBasisLanes] = {0.0, 1.0, dirs(0, 0), 0.0};
  const double y[kBasisLanes] = {0.0, 0.0, dirs(0, 1), -1.0};
  const double z[kBasisLanes] = {1.0, 0.0, dirs(0, 2), -1e-13};
  const double scale[kBasisLanes] = {1.0, 2.0, 0.5, 1.0};
  std::vector<double> scratch(static_cast<size_t>(hemisphere_basis_lanes_scratch(order))), out(static_cast<size_t>(m * kBasisLanes), 1.0);
  hemisphere_basis_eval_lanes(order, x, y, z, scale, scratch.data(), out.data(), true);  // adds to 1
  for (int l = 0; l < kBasisLanes; ++l) {
    Eigen::Vector3d d(x[l], y[l], std::max(z[l], 0.0));
    d.normalize();
    hemisphere_basis_eval(order, d, k.data());
    for (int j = 0; j < m; ++j)
      EXPECT_NEAR(out[static_cast<size_t>(j * kBasisLanes + l)], 1.0 + scale[l] * k[static_cast<size_t>(j)], kReorderTol * 10) << "lane " << l << " mode " << j;
  }
  // The Gram matrix of a symmetric grid (computed from one cell per orbit) equals B^T W B in full.
  const auto basis = build_discrete_basis(g, 6);
  ASSERT_TRUE(rows_are_d2_equivariant(g, basis.B, 1e-12));
  const Eigen::MatrixXd full = basis.B.transpose() * basis.W.asDiagonal() * basis.B;
  EXPECT_LT((basis.G - full).cwiseAbs().maxCoeff(), kAlgebraTol);
}

}  // namespace
}  // namespace icobrdf
