// Exports renderers load (icobrdf/pipeline/renderer_export.hpp): a MERL export read back at every node and
// between nodes, an RGL export of an RGL export, and the refusals (anisotropic sources, delta parts).
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <string>

#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/merl.hpp"
#include "icobrdf/pipeline/renderer_export.hpp"
#include "tests/io/io_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

using icobrdf::test::ScratchDir;
using namespace icobrdf;

// A MERL file stores f / scale_c as doubles and the reader multiplies by scale_c again: two roundings of half
// an ulp each, so every node comes back within 2 ulps of the source's value (4 for a margin).
constexpr double kMerlRoundTripTol = 4 * DBL_EPSILON;
// The RGL export's acceptance figure (cosine metric).
constexpr double kExportAgreement = 0.03;
// Central differences of f in the half/difference angles for the MERL error bound: a step small against
// the bins (0.5 deg) and large against rounding.
constexpr double kDerivativeStep = 1e-5;
constexpr int kPairs = 20000;
const char* const kGlossy = "model:ggx:alpha=0.3,f0=0.04";

Eigen::MatrixXd values(const BrdfModel& m, const RowMatrix3d& wi, const RowMatrix3d& wr) {
  Eigen::MatrixXd out(wi.rows(), m.channels());
  m.eval(wi, wr, out);
  return out;
}

TEST(RendererExport, MerlExportReadsBackAtEveryNodeWithinRounding) {
  ScratchDir d;
  const std::string out = d / "g.binary";
  const RendererExport e = export_for_renderer(kGlossy, "merl", out);
  EXPECT_LE(e.node_max_rel, kMerlRoundTripTol);
  EXPECT_EQ(e.negatives_zeroed, 0);
  const MerlTable t = read_merl(out);
  EXPECT_EQ(t.missing_total(), 0);
  const auto model = parse_model_source(kGlossy);
  const int row = kMerlThetaDiffRes * kMerlPhiDiffRes;
  RowMatrix3d wi(row, 3), wr(row, 3);
  double worst = 0;
  long long compared = 0;
  for (int ih = 0; ih < kMerlThetaHalfRes; ++ih) {
    for (int r = 0; r < row; ++r) {
      Eigen::Vector3d a, b;
      directions_from_half_diff(merl_node({ih, r / kMerlPhiDiffRes, r % kMerlPhiDiffRes}), a, b);
      wi.row(r) = a.transpose();
      wr.row(r) = b.transpose();
    }
    const Eigen::MatrixXd f = values(*model, wi, wr);
    for (int r = 0; r < row; ++r) {
      if (!(wi(r, 2) > 0 && wr(r, 2) > 0)) continue;
      const MerlBin bin{ih, r / kMerlPhiDiffRes, r % kMerlPhiDiffRes};
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(t.at(c, bin) - f(r, 0)) / f(r, 0));
      ++compared;
    }
  }
  EXPECT_GT(compared, kMerlSamplesPerChannel / 2);
  EXPECT_LE(worst, kMerlRoundTripTol);
}

// A MERL file exported again (the file as SOURCE): the lookup at a bin centre returns that bin's value, so
// the second table holds the first one's values up to the same two roundings per entry, at every bin whose
// directions are both above the horizon (the others hold what the source gives below it, which a MERL
// lookup does not return).
TEST(RendererExport, MerlExportOfAMerlExportIsTheSameTable) {
  ScratchDir d;
  const RendererExport first = export_for_renderer(kGlossy, "merl", d / "a.binary");
  const RendererExport second = export_for_renderer(d / "a.binary", "merl", d / "b.binary");
  EXPECT_LE(second.node_max_rel, kMerlRoundTripTol);
  const MerlTable a = read_merl(d / "a.binary"), b = read_merl(d / "b.binary");
  double worst = 0;
  long long compared = 0;
  for (std::int64_t flat = 0; flat < kMerlSamplesPerChannel; ++flat) {
    const MerlBin bin{static_cast<int>(flat / (kMerlPhiDiffRes * kMerlThetaDiffRes)), static_cast<int>(flat / kMerlPhiDiffRes % kMerlThetaDiffRes),
                      static_cast<int>(flat % kMerlPhiDiffRes)};
    Eigen::Vector3d wi, wr;
    directions_from_half_diff(merl_node(bin), wi, wr);
    if (!(wi.z() > 0 && wr.z() > 0)) continue;
    for (int c = 0; c < 3; ++c) {
      const double x = a.at(c, bin), y = b.at(c, bin);
      worst = std::max(worst, x == y ? 0.0 : std::abs(y - x) / std::abs(x));
    }
    ++compared;
  }
  EXPECT_GT(compared, kMerlSamplesPerChannel / 2);
  EXPECT_LE(worst, kMerlRoundTripTol);
  EXPECT_NEAR(second.cosine_l2, 0.0, kMerlRoundTripTol);  // the same table on both sides of the report
  std::printf("[ figures  ] MERL export of a MERL export of %s: largest relative difference at %lld bins %.3g; report %.3g (first %.4g)\n",
              kGlossy, compared, worst, second.cosine_l2, first.cosine_l2);
}

// Between nodes the MERL lookup is constant over each bin (icobrdf/io/merl.hpp), so to first order its error
// at a pair is at most sum_k |df/dq_k| h_k, q = (theta_h, theta_d, phi_d), h_k the largest distance from a
// point of the bin to its node: the bin width in theta_h (the node is the bin centre in sqrt(theta_h)) and
// half the width in theta_d and phi_d. The cosine-weighted L2 of the error stays within that of the bound.
TEST(RendererExport, MerlExportBetweenNodesIsWithinTheBinBound) {
  ScratchDir d;
  const std::string out = d / "g.binary";
  const RendererExport e = export_for_renderer(kGlossy, "merl", out);
  const auto model = parse_model_source(kGlossy);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto draw = [&] {
    const double z = u(rng), phi = 2 * M_PI * u(rng), s = std::sqrt(1 - z * z);
    return Eigen::Vector3d(s * std::cos(phi), s * std::sin(phi), z);
  };
  RowMatrix3d wi(kPairs, 3), wr(kPairs, 3), shifted_i(6 * kPairs, 3), shifted_r(6 * kPairs, 3);
  Eigen::MatrixXd reach(kPairs, 3);
  for (int k = 0; k < kPairs; ++k) {
    wi.row(k) = draw().transpose();
    wr.row(k) = draw().transpose();
    const HalfDiffAngles q = half_diff_from_directions(wi.row(k).transpose(), wr.row(k).transpose());
    const int ih = std::min(static_cast<int>(kMerlThetaHalfRes * std::sqrt(q.theta_h / (M_PI / 2))), kMerlThetaHalfRes - 1);
    reach.row(k) << (M_PI / 2) * (2 * ih + 1) / (kMerlThetaHalfRes * kMerlThetaHalfRes), 0.5 * (M_PI / 2) / kMerlThetaDiffRes,
        0.5 * M_PI / kMerlPhiDiffRes;
    for (int a = 0; a < 3; ++a)
      for (int sgn = 0; sgn < 2; ++sgn) {
        HalfDiffAngles s = q;
        double* angle[3] = {&s.theta_h, &s.theta_d, &s.phi_d};
        *angle[a] += sgn ? kDerivativeStep : -kDerivativeStep;
        Eigen::Vector3d a3, b3;
        directions_from_half_diff(s, a3, b3);
        shifted_i.row(6 * k + 2 * a + sgn) = a3.transpose();
        shifted_r.row(6 * k + 2 * a + sgn) = b3.transpose();
      }
  }
  const Eigen::MatrixXd f = values(*model, wi, wr), fs = values(*model, shifted_i, shifted_r);
  const Eigen::MatrixXd table = values(MerlModel(std::make_shared<const MerlTable>(read_merl(out))), wi, wr);
  double err = 0, bound = 0, norm = 0;
  for (int k = 0; k < kPairs; ++k) {
    const double w = wi(k, 2) * wr(k, 2);
    double b = 0;
    for (int a = 0; a < 3; ++a) b += std::abs(fs(6 * k + 2 * a + 1, 0) - fs(6 * k + 2 * a, 0)) / (2 * kDerivativeStep) * reach(k, a);
    err += w * w * (table(k, 0) - f(k, 0)) * (table(k, 0) - f(k, 0));
    bound += w * w * b * b;
    norm += w * w * f(k, 0) * f(k, 0);
  }
  const double rel_err = std::sqrt(err / norm), rel_bound = std::sqrt(bound / norm);
  EXPECT_LE(rel_err, rel_bound);
  EXPECT_NEAR(e.cosine_l2, rel_err, 0.5 * rel_err);  // the report's own draw estimates the same integral
  std::printf("[ figures  ] MERL export of %s between nodes: cosine-weighted relative L2 %.4g, first-order bin bound %.4g\n", kGlossy,
              rel_err, rel_bound);
}

TEST(RendererExport, AnRglExportOfAnRglExportAgreesWithIt) {
  ScratchDir d;
  const RendererExport first = export_for_renderer(kGlossy, "rgl", d / "a.bsdf");
  EXPECT_LE(first.cosine_l2, kExportAgreement);
  const RendererExport second = export_for_renderer(d / "a.bsdf", "rgl", d / "b.bsdf");
  EXPECT_LE(second.cosine_l2, kExportAgreement);
  std::printf("[ figures  ] RGL export of %s: %.4g; exported again from the file: %.4g\n", kGlossy, first.cosine_l2, second.cosine_l2);
}

TEST(RendererExport, RefusesAnisotropicSourcesDeltaPartsAndUnknownFormats) {
  ScratchDir d;
  for (const std::string format : {"rgl", "merl"}) {
    const auto message = [&](const std::string& source) {
      try {
        export_for_renderer(source, format, d / "x");
      } catch (const ArgumentError& e) {
        return std::string(e.what());
      }
      return std::string("no error");
    };
    EXPECT_NE(message("model:ggx-aniso:alpha_x=0.1,alpha_y=0.3").find("is anisotropic"), std::string::npos) << format;
    EXPECT_NE(message("model:0.5*lambert+0.5*mirror").find("has a delta part"), std::string::npos) << format;
  }
  EXPECT_THROW(export_for_renderer(kGlossy, "pdf", d / "x"), ArgumentError);
  EXPECT_TRUE(d.entries().empty());
}

}  // namespace ICOBRDF_UNITY_ID
