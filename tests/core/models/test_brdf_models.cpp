// Properties every analytic model must have: Helmholtz reciprocity, isotropy where claimed, finite and
// non-negative values at normal, grazing and horizon directions, zero below the horizon, delta parts.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "icobrdf/core/models/brdf_model.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "tests/core/brdf_quadrature.hpp"
#include "tests/support/unity_id.hpp"

using namespace icobrdf;
using icobrdf::test::dir_deg;

namespace ICOBRDF_UNITY_ID {

// Every formula is symmetric term by term; with fused multiply-adds the two orders may round a sum
// differently by an ulp of its largest term, which a lobe exponent (<= 200 here) and cancellation in
// the lobe base (Lafortune, cx != cy) amplify to a few 1e-14 at most.
constexpr double kReciprocityTol = 1e-12;
// Rotating the inputs about z perturbs them by ~1e-16; the steepest lobes tested (exponent <= 200,
// roughness >= 0.05) amplify that by < 1e4.
constexpr double kIsotropyTol = 1e-11;
// A change this large under rotation is anisotropy, not rounding.
constexpr double kAnisotropyMin = 0.05;

// Registry defaults plus parameter sets covering the branches (fresnel, masking, k < 1, lobes, sums).
std::vector<std::string> model_specs() {
  std::vector<std::string> specs;
  for (const auto& info : model_registry()) specs.push_back(info.name);
  for (const char* s : {"lambert:albedo=0.3", "minnaert:k=0.5", "minnaert:k=0", "minnaert:k=3", "minnaert:k=2.7",
                        "phong:n=0", "phong:n=3.5,ks=0.6", "blinn-phong:n=0.5", "blinn-phong:n=200",
                        "ggx:alpha=0.05", "ggx:alpha=1.5,fresnel=dielectric,ior=1.8",
                        "ggx:alpha=0.3,fresnel=none,masking=separable", "beckmann:alpha=0.05",
                        "beckmann:alpha=0.8,masking=separable,fresnel=dielectric",
                        "ggx-aniso:alpha_x=0.05,alpha_y=0.5,azimuth=30",
                        "lafortune:cx=-1.2,cy=-0.8,cz=0.9,n=7.5,azimuth=20", "lafortune:cx=0.9,cy=0.9,cz=0.9,n=3",
                        "oren-nayar:sigma=40,albedo=0.6", "oren-nayar:sigma=0", "hapke:w=1", "hapke:w=0",
                        "lommel-seeliger:w=0.4", "0.3*lambert+0.7*ggx:alpha=0.2", "mirror+0.05*lambert",
                        "0.5*hapke:w=0.9+0.25*lafortune:cx=-1,cy=-0.5,cz=1,n=4,azimuth=45"})
    specs.push_back(s);
  return specs;
}

Eigen::VectorXd eval_all(const BrdfModel& m, const RowMatrix3d& wi, const RowMatrix3d& wr) {
  Eigen::MatrixXd out(wi.rows(), m.channels());
  m.eval(wi, wr, out);
  return out.col(0);
}

RowMatrix3d rotate_z(const RowMatrix3d& w, double angle) {
  RowMatrix3d r(w.rows(), 3);
  const double c = std::cos(angle), s = std::sin(angle);
  for (Eigen::Index k = 0; k < w.rows(); ++k) r.row(k) << c * w(k, 0) - s * w(k, 1), s * w(k, 0) + c * w(k, 1), w(k, 2);
  return r;
}

TEST(BrdfModels, ReciprocityAtRandomGrazingAndNormalPairs) {
  const auto pairs = test::test_pairs(2000);
  double worst = 0.0;
  for (const auto& spec : model_specs()) {
    const auto m = parse_model(spec);
    ASSERT_TRUE(m->is_reciprocal()) << spec;
    const Eigen::VectorXd f = eval_all(*m, pairs.wi, pairs.wr), g = eval_all(*m, pairs.wr, pairs.wi);
    double model_worst = 0.0;
    for (Eigen::Index k = 0; k < f.size(); ++k) {
      const double rel = std::abs(f(k) - g(k)) / std::max({std::abs(f(k)), std::abs(g(k)), 1e-300});
      model_worst = std::max(model_worst, f(k) == g(k) ? 0.0 : rel);
    }
    EXPECT_LE(model_worst, kReciprocityTol) << spec;
    worst = std::max(worst, model_worst);
  }
  std::cout << "max relative reciprocity error over all models: " << worst << "\n";
  RecordProperty("max_reciprocity_error", std::to_string(worst));
}

TEST(BrdfModels, IsotropicModelsAreInvariantUnderRotationAboutTheNormal) {
  const auto pairs = test::test_pairs(500);
  for (const auto& spec : model_specs()) {
    const auto m = parse_model(spec);
    if (!m->is_isotropic()) continue;
    const Eigen::VectorXd f = eval_all(*m, pairs.wi, pairs.wr);
    for (double angle : {0.3, 1.7, M_PI}) {
      const Eigen::VectorXd g = eval_all(*m, rotate_z(pairs.wi, angle), rotate_z(pairs.wr, angle));
      for (Eigen::Index k = 0; k < f.size(); ++k)
        ASSERT_NEAR(g(k), f(k), kIsotropyTol * std::max(1.0, std::abs(f(k))))
            << spec << " pair " << k << " angle " << angle;
    }
  }
}

TEST(BrdfModels, AnisotropicModelsChangeUnderRotation) {
  for (const char* spec : {"ggx-aniso", "ggx-aniso:alpha_x=0.05,alpha_y=0.5,azimuth=30",
                           "lafortune:cx=-1.2,cy=-0.8,cz=0.9,n=7.5,azimuth=20"}) {
    const auto m = parse_model(spec);
    EXPECT_FALSE(m->is_isotropic()) << spec;
    EXPECT_TRUE(m->is_reciprocal()) << spec;
    const auto pairs = test::test_pairs(200);
    const Eigen::VectorXd f = eval_all(*m, pairs.wi, pairs.wr);
    const Eigen::VectorXd g = eval_all(*m, rotate_z(pairs.wi, 0.9), rotate_z(pairs.wr, 0.9));
    double biggest = 0.0;
    for (Eigen::Index k = 0; k < f.size(); ++k)
      biggest = std::max(biggest, std::abs(f(k) - g(k)) / std::max(std::abs(f(k)), 1e-12));
    EXPECT_GT(biggest, kAnisotropyMin) << spec;
  }
  // Equal widths make ggx-aniso isotropic and equal to ggx.
  const auto a = parse_model("ggx-aniso:alpha_x=0.25,alpha_y=0.25,azimuth=33");
  const auto b = parse_model("ggx:alpha=0.25");
  EXPECT_TRUE(a->is_isotropic());
  const auto pairs = test::test_pairs(300);
  const Eigen::VectorXd fa = eval_all(*a, pairs.wi, pairs.wr), fb = eval_all(*b, pairs.wi, pairs.wr);
  for (Eigen::Index k = 0; k < fa.size(); ++k) ASSERT_NEAR(fa(k), fb(k), kIsotropyTol * std::max(1.0, fb(k))) << k;
}

TEST(BrdfModels, AzimuthRotatesTheAnisotropicFrame) {
  // Rotating the tangent frame by psi equals rotating both directions by -psi.
  const auto m0 = parse_model("ggx-aniso:alpha_x=0.1,alpha_y=0.4,azimuth=0");
  const auto m1 = parse_model("ggx-aniso:alpha_x=0.1,alpha_y=0.4,azimuth=40");
  const auto pairs = test::test_pairs(300);
  const double psi = 40.0 * M_PI / 180.0;
  const Eigen::VectorXd f1 = eval_all(*m1, pairs.wi, pairs.wr);
  const Eigen::VectorXd f0 = eval_all(*m0, rotate_z(pairs.wi, -psi), rotate_z(pairs.wr, -psi));
  for (Eigen::Index k = 0; k < f0.size(); ++k) ASSERT_NEAR(f1(k), f0(k), kIsotropyTol * std::max(1.0, f0(k))) << k;
}

TEST(BrdfModels, FiniteNonNegativeEverywhereOnTheHemisphereAndZeroBelow) {
  const auto pairs = test::test_pairs(1000);
  for (const auto& spec : model_specs()) {
    const auto m = parse_model(spec);
    const Eigen::VectorXd f = eval_all(*m, pairs.wi, pairs.wr);
    for (Eigen::Index k = 0; k < f.size(); ++k) {
      ASSERT_TRUE(std::isfinite(f(k))) << spec << " pair " << k;
      ASSERT_GE(f(k), 0.0) << spec << " pair " << k;
    }
    // Below the horizon: 0, for either direction.
    const Eigen::Vector3d up = dir_deg(30, 10), down(0.3, 0.1, -std::sqrt(1 - 0.1));
    EXPECT_EQ(m->eval(up, down), 0.0) << spec;
    EXPECT_EQ(m->eval(down, up), 0.0) << spec;
    // Within the horizon slack: the value on the horizon.
    const Eigen::Vector3d on(0.6, 0.8, 0.0), slack(0.6, 0.8, -0.5 * kHorizonSlack);
    EXPECT_EQ(m->eval(slack, up), m->eval(on, up)) << spec;
  }
}

TEST(BrdfModels, DivergentFactorsAreFlooredAtTheDocumentedCosine) {
  // Minnaert k = 0.5 at a grazing pair: (k+1)/(2 pi) (c_i c_r)^(k-1) with c floored at kGrazingCosFloor.
  const auto m = parse_model("minnaert:k=0.5");
  const Eigen::Vector3d horizon(1.0, 0.0, 0.0), normal(0.0, 0.0, 1.0);
  EXPECT_DOUBLE_EQ(m->eval(horizon, normal), 1.5 / (2 * M_PI) * std::pow(kGrazingCosFloor, -0.5));
  EXPECT_DOUBLE_EQ(m->eval(horizon, horizon), 1.5 / (2 * M_PI) * std::pow(kGrazingCosFloor, -1.0));
  // Lommel-Seeliger at double grazing: w/(4 pi floor).
  EXPECT_DOUBLE_EQ(parse_model("lommel-seeliger:w=1")->eval(horizon, Eigen::Vector3d(0, 1, 0)),
                   1.0 / (4 * M_PI * kGrazingCosFloor));
  // Just above the floor the formula is used as is: at theta = 89.9 deg for both.
  const Eigen::Vector3d g1 = dir_deg(89.9, 0), g2 = dir_deg(89.9, 120);
  EXPECT_DOUBLE_EQ(parse_model("lommel-seeliger:w=1")->eval(g1, g2), 1.0 / (4 * M_PI * (g1.z() + g2.z())));
}

TEST(BrdfModels, MirrorAndRetroreflectorAreDeltaOnly) {
  const auto pairs = test::test_pairs(50);
  for (const char* spec : {"mirror", "retroreflector"}) {
    const auto m = parse_model(spec);
    EXPECT_EQ(eval_all(*m, pairs.wi, pairs.wr).cwiseAbs().maxCoeff(), 0.0) << spec;
    const auto parts = m->delta_parts();
    ASSERT_EQ(parts.size(), 1u);
    EXPECT_EQ(parts[0].kind, std::string(spec) == "mirror" ? DeltaPart::Mirror : DeltaPart::Retroreflector);
    EXPECT_EQ(parts[0].weight, 1.0);
  }
  for (const auto& info : model_registry())
    EXPECT_EQ(info.delta, !parse_model(info.name)->delta_parts().empty()) << info.name;
}

TEST(BrdfModels, ShapeMismatchIsAnArgumentError) {
  const auto m = parse_model("lambert");
  RowMatrix3d a(3, 3), b(2, 3);
  a.setZero();
  b.setZero();
  Eigen::MatrixXd out(3, 1);
  EXPECT_THROW(m->eval(a, b, out), ArgumentError);
  Eigen::MatrixXd wide(3, 2);
  EXPECT_THROW(m->eval(a, a, wide), ArgumentError);
}

}  // namespace ICOBRDF_UNITY_ID
