// The noise figure of RGL materials (icobrdf/io/rgl_bsdf.hpp RglBsdf::noise_sigma, RglModel::noise_sigma, the
// SOURCE's noise_sigma_at). The file's value tables are constants plus Gaussian noise of a known sigma per slice,
// so each table's estimate is judged against the sigma drawn (icobrdf/core/tables/grid_noise.hpp: its standard
// error), and the noise at a pair against the format's definition: the slices' variances blended with the
// parameter weights, times the factor eval applies (D / (4 sigma) with the jacobian, 1 / cos(theta_r)).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <random>
#include <vector>

#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/rgl_bsdf.hpp"
#include "io_test_support.hpp"
#include "rgl_test_files.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

// Relative standard error of a table's estimate from N second differences (grid_noise.hpp), judged within 4 of
// them (the draws are seeded: deterministic).
constexpr double kMadStandardError = 1.67, kStandardErrors = 4.0;
// Double rounding of the blend and the direction arithmetic (a few operations on values of order 1).
constexpr double kRounding = 1e-12;
constexpr int kSide = 65;                              // nodes per side of the value tables
constexpr double kLevel = 0.5;                         // the tables' constant value
constexpr double kSliceSigma[2] = {0.005, 0.015};      // noise per theta_i slice (1 % and 3 % of the level)
constexpr double kNdf = 2.0, kProjectedArea = 0.25;    // jacobian factor D / (4 sigma) = 2

test::RglFileSpec noisy_constant_file() {
  test::RglFileSpec s;
  s.theta = {0.25, 1.0};
  s.w = kSide;
  s.h = kSide;
  s.jacobian = true;
  s.ndf = kNdf;
  s.sigma = kProjectedArea;
  auto draws = std::make_shared<std::vector<double>>();
  std::mt19937_64 rng(21);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int k = 0; k < 2 * 3 * kSide * kSide; ++k) draws->push_back(n(rng));
  s.value = [draws](int, int t, int c, int k, int j) {
    return kLevel + kSliceSigma[t] * (*draws)[static_cast<size_t>(((t * 3 + c) * kSide + j) * kSide + k)];
  };
  return s;
}

TEST(RglNoise, EachTableEstimatesTheNoiseDrawnIntoIt) {
  test::ScratchDir d;
  write_tensor_file(d / "noisy.bsdf", test::rgl_fields(noisy_constant_file()));
  const RglBsdf b = read_rgl_bsdf(d / "noisy.bsdf");
  ASSERT_EQ(b.noise_sigma.size(), 6u);  // 1 phi x 2 theta x 3 channels, in the values' slice order
  const double differences = 2.0 * kSide * (kSide - 2);
  const double tol = kStandardErrors * kMadStandardError / std::sqrt(differences);
  for (int t = 0; t < 2; ++t)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(b.noise_sigma[static_cast<size_t>(t * 3 + c)] / kSliceSigma[t], 1.0, tol) << "slice " << t << " channel " << c;
}

TEST(RglNoise, NoiseAtPairsIsTheBlendOfTheSlicesTimesEvalsFactor) {
  test::ScratchDir d;
  write_tensor_file(d / "noisy.bsdf", test::rgl_fields(noisy_constant_file()));
  const auto src = open_source(d / "noisy.bsdf");
  const RglBsdf b = read_rgl_bsdf(d / "noisy.bsdf");
  // Incidence at the slices and between them (linear weights in theta_i), outgoing directions at several heights.
  const double thetas_i[] = {0.25, 0.4, 0.625, 1.0}, thetas_r[] = {0.1, 0.7, 1.3};
  RowMatrix3d wi(12, 3), wr(12, 3);
  int row = 0;
  for (const double ti : thetas_i)
    for (const double tr : thetas_r) {
      wi.row(row) << std::sin(ti), 0.0, std::cos(ti);
      wr.row(row++) << -std::sin(tr) * 0.6, std::sin(tr) * 0.8, std::cos(tr);
    }
  const std::optional<Eigen::MatrixXd> sigma = src->noise_sigma_at(wi, wr);
  ASSERT_TRUE(sigma.has_value());
  ASSERT_EQ(sigma->rows(), 12);
  ASSERT_EQ(sigma->cols(), 3);
  for (Eigen::Index k = 0; k < 12; ++k) {
    const double ti = std::acos(wi(k, 2)), t = std::clamp((ti - 0.25) / 0.75, 0.0, 1.0);
    const double factor = kNdf / (4 * kProjectedArea) / wr(k, 2);
    for (int c = 0; c < 3; ++c) {
      const double s0 = b.noise_sigma[static_cast<size_t>(c)], s1 = b.noise_sigma[static_cast<size_t>(3 + c)];
      const double expected = std::sqrt((1 - t) * s0 * s0 + t * s1 * s1) * factor;
      EXPECT_NEAR((*sigma)(k, c), expected, kRounding * expected) << "pair " << k << " channel " << c;
    }
  }
  // Below the horizon: no value, no noise. A model has no grid: no estimate.
  RowMatrix3d below = wr;
  below.col(2) *= -1.0;
  EXPECT_EQ(src->noise_sigma_at(wi, below)->cwiseAbs().maxCoeff(), 0.0);
  EXPECT_FALSE(open_source("model:lambert")->noise_sigma_at(wi, wr).has_value());
}

}  // namespace ICOBRDF_UNITY_ID
}  // namespace icobrdf
