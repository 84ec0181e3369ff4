// The half-angle search on measured data (icobrdf/pipeline/half_angle_representation.hpp): a target below the
// data's noise stops the search at once, keeps the best lobe within the budget, and the report explains the
// miss by the noise (icobrdf/pipeline/material_report.hpp kNoiseMargin).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>

#include "icobrdf/core/models/function_model.hpp"
#include "icobrdf/core/support/scramble.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/pipeline/bank_builder.hpp"
#include "icobrdf/pipeline/held_out.hpp"
#include "icobrdf/pipeline/material_candidate.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

// f = g (1 + e n(w_i, w_r)) with g = 1/pi (Lambert: a rank-1 lobe in the mean-cosine quantity, cos_i + cos_r
// = 2 cos theta_h cos theta_d) and n of unit variance, drawn independently for each ordered pair (hash of the
// eight coordinates' bits), so that n(a, b) and n(b, a) are independent. Then, in expectation over the pairs,
//   asymmetry^2            = |w g e (n_ab - n_ba)/2|^2 / |w g|^2 = e^2 / 2
//   |w (g - f_rec)|^2/|w f_rec|^2 = |w g e (n_ab + n_ba)/2|^2 / |w g|^2 = e^2 / 2   (up to 1 + e^2/2)
// so a lobe holding g is the asymmetry away from the reciprocal part: the noise, not the lobe, sets the floor.
constexpr double kE = 0.1;
double noise(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Index k) {
  std::uint64_t h = 0x6e6f697365ULL;
  const double v[6] = {wi(k, 0), wi(k, 1), wi(k, 2), wr(k, 0), wr(k, 1), wr(k, 2)};
  for (const double x : v) {
    std::uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    h = splitmix64(h ^ bits);
  }
  const double u = static_cast<double>(h >> 11) * 0x1.0p-53;  // [0, 1)
  return std::sqrt(3.0) * (2 * u - 1);                        // unit variance
}

std::unique_ptr<BrdfSource> noisy_lambert() {
  auto values = [](const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) {
    for (Eigen::Index k = 0; k < wi.rows(); ++k) out(k, 0) = (1 + kE * noise(wi, wr, k)) / M_PI;
  };
  return model_source(std::make_unique<FunctionModel>(1, values, "noisy-lambert", true, false));
}

// The two estimates above agree in expectation; 4,096 held-out pairs leave each a few per cent of sampling
// error, and the lobe's own interpolation error adds to the error in quadrature.
constexpr double kEstimatesAgree = 1.25;

TEST(MeasuredSearch, ATargetBelowTheNoiseStopsAtOnceAndIsExplainedByTheNoise) {
  const auto src = noisy_lambert();
  ASSERT_FALSE(src->reciprocal_by_construction());
  Scene s;
  s.representations = {"half-angle", "hybrid"};
  SceneMaterial m;
  m.name = "noisy";
  m.source = "model:noisy-lambert";
  m.target = 0.02;  // below the noise e / sqrt(2) = 0.071
  m.isotropic = IsotropicChoice::Always;
  m.max_bytes = 65536;
  m.on_miss = OnMiss::KeepBest;
  const HeldOutSplit h = held_out_split(s, m, *src);
  ASSERT_TRUE(h.reciprocal_reference);
  EXPECT_NEAR(h.asymmetry, kE / std::sqrt(2.0), (kEstimatesAgree - 1) * kE / std::sqrt(2.0));
  const HeldOutErrors errors(h.pairs, 0, m.metric, true);
  FitContexts contexts;
  const auto t0 = std::chrono::steady_clock::now();
  const MaterialProblem p{s, m, *src, &errors, contexts, [](const std::string&) {}};
  const MaterialCandidate c = choose_representation(p);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(c.representation, "half-angle");  // the best lobe, not a fallback to the modes (not allowed here)
  EXPECT_FALSE(c.target_met);
  EXPECT_LE(c.bytes, m.max_bytes);
  EXPECT_FALSE(c.note.empty());
  EXPECT_GT(c.error.l2, h.asymmetry / kEstimatesAgree);
  EXPECT_LT(c.error.l2, h.asymmetry * kEstimatesAgree);
  MaterialReport rep;
  rep.measured = true;
  rep.target_met = false;
  rep.error_l2 = c.error.l2;
  rep.asymmetry = h.asymmetry;
  rep.reciprocal_reference = true;
  explain_miss(c, rep);
  EXPECT_TRUE(rep.below_noise);
  EXPECT_NE(rep.note.find("noise"), std::string::npos) << rep.note;
  std::cout << "noisy Lambert: asymmetry " << h.asymmetry << ", lobe " << c.error.l2 << " (" << c.bytes << " B), " << seconds
            << " s; " << rep.note << "\n";
}

}  // namespace ICOBRDF_UNITY_ID
}  // namespace icobrdf
