// The data's noise figure of a material (icobrdf/pipeline/held_out.hpp `noise`) and where it is reported: the
// miss explanation (explain_miss), the report's JSON and table, the bank's choice figures.
// The data: an RGL file whose value tables are a constant L plus Gaussian noise of sigma (tests/io/rgl_test_files.hpp).
// In the cosine metric w f = cos_i cos_r v J / max(cos_r, floor) and w sigma_f = the same with v -> sigma, so
//   noise = |w sigma| / |w f| = sigma / L   up to the held-out values' own noise: |v^2 - L^2| / L^2 <= 2 e + e^2,
// e = the largest |v - L| / L at a held-out pair (< 5 sigma / L for the 3 x 65 x 65 Gaussian draws: their largest
// is 4.3 sigma) and the table's estimate of sigma (its standard error, icobrdf/core/tables/grid_noise.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/rgl_bsdf.hpp"
#include "icobrdf/pipeline/bank_builder.hpp"
#include "icobrdf/pipeline/bank_report.hpp"
#include "icobrdf/pipeline/bank_resume.hpp"
#include "icobrdf/pipeline/held_out.hpp"
#include "icobrdf/pipeline/material_problem.hpp"
#include "tests/io/io_test_support.hpp"
#include "tests/io/rgl_test_files.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

constexpr int kSide = 65;
constexpr double kLevel = 0.5, kSigma = 0.005;  // noise 1 % of the level
// The table's estimate within 4 standard errors (1.67 / sqrt(N) relative, N = 2 x 65 x 63 differences) and the
// held-out values' own noise (5 sigma / L, above): the figure's relative tolerance against sigma / L.
const double kFigureTol = 4 * 1.67 / std::sqrt(2.0 * kSide * (kSide - 2)) + 5 * kSigma / kLevel;
// Sums over a few thousand pairs of products of order 1: double rounding.
constexpr double kRounding = 1e-12;

std::string write_noisy_file(const test::ScratchDir& d) {
  test::RglFileSpec s;
  s.theta = {0.5};
  s.w = kSide;
  s.h = kSide;
  auto draws = std::make_shared<std::vector<double>>();
  std::mt19937_64 rng(31);
  std::normal_distribution<double> n(0.0, kSigma);
  for (int k = 0; k < 3 * kSide * kSide; ++k) draws->push_back(n(rng));
  s.value = [draws](int, int, int c, int k, int j) { return kLevel + (*draws)[static_cast<size_t>((c * kSide + j) * kSide + k)]; };
  write_tensor_file(d / "noisy.bsdf", test::rgl_fields(s));
  return d / "noisy.bsdf";
}

TEST(DataNoise, HeldOutFigureIsTheNoiseOverTheLevelInTheMetric) {
  test::ScratchDir d;
  const std::string path = write_noisy_file(d);
  const auto src = open_source(path);
  Scene scene;
  scene.holdout_pairs = 2000;
  SceneMaterial m;
  m.name = "noisy";
  m.source = path;
  const HeldOutSplit h = held_out_split(scene, m, *src);
  ASSERT_TRUE(std::isfinite(h.noise));
  EXPECT_NEAR(h.noise / (kSigma / kLevel), 1.0, kFigureTol);
  // The definition at the held-out pairs, recomputed: |w sigma| / |w f| with w = cos_i cos_r and f the raw values.
  const Eigen::MatrixXd f = src->eval(h.pairs.wi, h.pairs.wr), sigma = *src->noise_sigma_at(h.pairs.wi, h.pairs.wr);
  double num = 0, den = 0;
  for (Eigen::Index k = 0; k < f.rows(); ++k) {
    const double w = h.pairs.wi(k, 2) * h.pairs.wr(k, 2);
    num += w * w * sigma.row(k).squaredNorm();
    den += w * w * f.row(k).squaredNorm();
  }
  EXPECT_NEAR(h.noise, std::sqrt(num / den), kRounding);
  // A model has no grid: not available.
  const auto model = open_source("model:lambert");
  SceneMaterial lm = m;
  lm.source = "model:lambert";
  EXPECT_TRUE(std::isnan(held_out_split(scene, lm, *model).noise));
}

MaterialReport missed(double error, double noise) {
  MaterialReport rep;
  rep.name = "noisy";
  rep.ok = true;
  rep.target = 0.001;
  rep.target_met = false;
  rep.error_l2 = error;
  rep.asymmetry = 0.0;  // none: the noise figure alone explains
  rep.noise = noise;
  rep.reciprocal_reference = true;
  return rep;
}

TEST(DataNoise, AMissWithinTheNoiseIsExplainedAndReported) {
  const MaterialCandidate c;
  MaterialReport within = missed(0.011, 0.01), above = missed(0.02, 0.01);
  explain_miss(c, within);
  explain_miss(c, above);
  EXPECT_TRUE(within.below_noise);  // 0.011 <= kNoiseMargin x 0.01
  EXPECT_NE(within.note.find("the data's noise 0.01: the error is within it"), std::string::npos) << within.note;
  EXPECT_FALSE(above.below_noise);  // 0.02 > 1.25 x 0.01
  EXPECT_NE(above.note.find("the data's noise 0.01: the error is above it"), std::string::npos) << above.note;

  EXPECT_EQ(material_report_json(within)["noise"].get<double>(), 0.01);
  EXPECT_TRUE(material_report_json(missed(0.02, std::nan("")))["noise"].is_null());
  BankBuildResult r;
  r.materials = {within};
  const std::string table = bank_build_table(r, "out.h5");
  EXPECT_NE(table.find("     asym     noise"), std::string::npos) << table;
  EXPECT_NE(table.find("        0      0.01 "), std::string::npos) << table;  // the asymmetry (0), then the figure

  // The bank's choice figures keep it; a resumed material reads it back; a source without a grid stores none.
  MaterialRecord rec;
  store_choice(rec, within);
  ASSERT_EQ(rec.figures.count("noise"), 1u);
  MaterialReport back;
  report_from_record(rec, back);
  EXPECT_EQ(back.noise, 0.01);
  MaterialRecord none;
  store_choice(none, missed(0.02, std::nan("")));
  EXPECT_EQ(none.figures.count("noise"), 0u);
}

}  // namespace ICOBRDF_UNITY_ID
}  // namespace icobrdf
