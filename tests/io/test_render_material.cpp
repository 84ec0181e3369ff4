// RenderMaterial (icobrdf/io/render_material.hpp): per-sample eval / pdf / sample for renderers, tested as
// pbrt-v4 tests its BxDFs: per-sample values against the batch evaluations they must reproduce, reciprocity,
// chi-squared tests of sample() against pdf() for every representation, the mean weight against the
// directional albedo by an independent Gauss-Legendre quadrature of f cos, the spread of the weights, and
// delta parts. Seeds are fixed.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/fit/half_angle_fit.hpp"
#include "icobrdf/core/grid/gauss_legendre.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/spectrum/analytic_spectra.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/material_eval.hpp"
#include "icobrdf/io/render_material.hpp"
#include "tests/support/chi_square.hpp"
#include "tests/support/unity_id.hpp"

using namespace icobrdf;

namespace ICOBRDF_UNITY_ID {

// Sample means against their expectation within 5 standard errors: a false failure has probability 6e-7 per
// comparison for a normal mean.
constexpr double kStandardErrors = 5.0;
// Per-sample model values against the vectorized batch kernel: a few ulps (icobrdf/core/models/microfacet.hpp).
constexpr double kKernelRelTol = 1e-12;
// Modes per pair against the batch evaluation: the same sums in another order, rounding only.
constexpr double kModesRelTol = 1e-12;
// The float forms are the double values rounded to float: 2^-24 relative, twice for a value computed from
// rounded inputs whose rounding moves f by up to its slope times 6e-8.
constexpr double kFloatRelTol = 1e-5;
// Issue's targets for the relative standard deviation of the weights f cos / pdf.
constexpr double kRsdNarrow = 0.15;  // GGX alpha 0.05
constexpr double kRsdWide = 0.05;    // GGX alpha 0.3
// 128 x 256 Gauss-Legendre nodes in (cos theta, phi) integrate the albedo of the test materials to better
// than 1e-4 relative (the narrowest, alpha 0.05, is checked here at a wider tolerance of the MC error only).
constexpr int kQuadCos = 128, kQuadPhi = 256;
// sample() reports the density at the cell and position it drew; pdf() finds them again from (w_i, w_r): the
// rounding of h (1e-16) over the pole cell's cos range (1.2e-6 with 32 t bins) moves the position by 1e-10,
// the linear density by twice that.
constexpr double kPdfRoundTripRelTol = 1e-8;
// Chi-squared tests of this file share the significance 1e-3 (Sidak correction over them).
constexpr int kChiSquareCases = 30;
const double kSignificance = 1.0 - std::pow(1.0 - 1e-3, 1.0 / kChiSquareCases);

std::shared_ptr<const BrdfModel> model(const std::string& spec) { return std::shared_ptr<const BrdfModel>(parse_model_source(spec)); }

// A lobe fitted to a model (the bank's half-angle representation of it).
const HalfAngleFactors& fitted_lobe(const std::string& spec) {
  static std::map<std::string, HalfAngleFactors> cache;
  auto it = cache.find(spec);
  if (it != cache.end()) return it->second;
  const auto m = model(spec);
  HalfAngleFitOptions o;
  o.max_rank = 4;
  o.target = 0.02;
  return cache.emplace(spec, fit_half_angle(model_pair_sampler(*m), 1, o).factors).first->second;
}

Spectrum minnaert_spectrum(int k) {
  Spectrum s;
  s.order = 2 * (k - 1);
  s.isotropic = true;
  s.channels = {minnaert_coefficients(s.order, k)};
  s.source = "minnaert spectrum";
  return s;
}

Spectrum zero_spectrum() {
  Spectrum s;
  s.order = 0;
  s.isotropic = true;
  s.channels = {Eigen::MatrixXd::Zero(1, 1)};
  s.source = "lobe";
  return s;
}

RenderMaterialOptions tables(int theta_nodes, int bins) {
  RenderMaterialOptions o;
  o.table.theta_nodes = theta_nodes;
  o.table.t_bins = bins;
  o.table.phi_bins = bins;
  return o;
}

// Coarse tables for the tests that check consistency and unbiasedness, not the spread of the weights.
RenderMaterialOptions coarse() { return tables(8, 32); }

RenderMaterial lobe_material(const std::string& spec, const RenderMaterialOptions& o = {}) {
  return RenderMaterial(zero_spectrum(), fitted_lobe(spec), o);
}

// Directional albedo of the material's regular part at w_i by Gauss-Legendre in (cos theta_r, phi_r).
double albedo_by_quadrature(const RenderMaterial& m, const Eigen::Vector3d& wi, int channel = 0) {
  const QuadratureRule gz = gauss_legendre(kQuadCos, 0.0, 1.0), gp = gauss_legendre(kQuadPhi, -M_PI, M_PI);
  double s = 0.0;
  for (int a = 0; a < kQuadCos; ++a)
    for (int b = 0; b < kQuadPhi; ++b) {
      const double z = gz.nodes[a], st = std::sqrt(std::max(0.0, 1 - z * z));
      const Eigen::Vector3d wr(st * std::cos(gp.nodes[b]), st * std::sin(gp.nodes[b]), z);
      s += gz.weights[a] * gp.weights[b] * m.eval(wi, wr)[channel] * z;
    }
  return s;
}

struct WeightStats {
  double mean = 0, sd = 0;
  int valid = 0, delta = 0;
};
WeightStats weight_stats(const RenderMaterial& m, const Eigen::Vector3d& wi, int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double s = 0, s2 = 0;
  WeightStats r;
  for (int i = 0; i < n; ++i) {
    const MaterialSample<double> d = m.sample(wi, u(rng), u(rng));
    const double w = d.valid() ? d.weight[0] : 0.0;
    r.valid += d.valid();
    r.delta += d.is_specular();
    s += w, s2 += w * w;
  }
  r.mean = s / n;
  r.sd = std::sqrt(std::max(0.0, s2 / n - r.mean * r.mean));
  return r;
}

std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> random_pairs(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> p;
  for (int i = 0; i < n; ++i) {
    const double ti = std::acos(u(rng)), tr = std::acos(u(rng));
    p.push_back({direction_from_angles(ti, 2 * M_PI * u(rng)), direction_from_angles(tr, 2 * M_PI * u(rng))});
  }
  return p;
}

TEST(RenderMaterial, PerSampleEvalEqualsTheBatchEvaluation) {
  const auto pairs = random_pairs(300, 11);
  RowMatrix3d wi(300, 3), wr(300, 3);
  for (int i = 0; i < 300; ++i) wi.row(i) = pairs[i].first.transpose(), wr.row(i) = pairs[i].second.transpose();
  // A stored lobe: bitwise (the same per-pair code).
  const HalfAngleFactors& lobe = fitted_lobe("model:ggx:alpha=0.3");
  const RenderMaterial lm(zero_spectrum(), lobe, coarse());
  const Eigen::MatrixXd lb = add_lobe(Eigen::MatrixXd::Zero(300, 1), lobe, wi, wr);
  for (int i = 0; i < 300; ++i) EXPECT_EQ(lm.eval(pairs[i].first, pairs[i].second)[0], lb(i, 0)) << i;
  // Models, sums included: the pair formula against the vectorized kernel.
  for (const std::string spec : {"model:0.4*lambert+0.6*ggx:alpha=0.2", "model:ggx-aniso:alpha_x=0.1,alpha_y=0.4,azimuth=30",
                                 "model:beckmann:alpha=0.2", "model:oren-nayar:sigma=20"}) {
    const RenderMaterial m = RenderMaterial::open(spec, coarse());
    const Eigen::MatrixXd b = open_source(spec)->eval(wi, wr);
    for (int i = 0; i < 300; ++i)
      EXPECT_NEAR(m.eval(pairs[i].first, pairs[i].second)[0], b(i, 0), kKernelRelTol * std::abs(b(i, 0)) + 1e-300) << spec << " " << i;
  }
  // Modes and hybrid (modes + lobe).
  const Spectrum s = minnaert_spectrum(3);
  for (const bool with_lobe : {false, true}) {
    const std::optional<HalfAngleFactors> l = with_lobe ? std::optional<HalfAngleFactors>(lobe) : std::nullopt;
    const RenderMaterial m(s, l, coarse());
    const Eigen::MatrixXd b = evaluate_material(s, l, wi, wr);
    for (int i = 0; i < 300; ++i)
      EXPECT_NEAR(m.eval(pairs[i].first, pairs[i].second)[0], b(i, 0), kModesRelTol * (1 + std::abs(b(i, 0)))) << with_lobe << " " << i;
  }
}

// Modes per sample (the basis at both directions in one pass, the contraction over columns padded to four
// rows) against the batch evaluation, at orders that change the padding (1: 3 -> 4 rows; 5: 21 -> 24; 6: 28,
// none) and the per-sample limit (20: 231 modes), three channels of different random matrices that are not
// symmetric (a swapped w_i and w_r, or channel, would show), with and without the cosine division, beside a
// lobe and alone.
TEST(RenderMaterial, ModesOfEveryOrderAndChannelEqualTheBatch) {
  const auto pairs = random_pairs(200, 23);
  RowMatrix3d wi(200, 3), wr(200, 3);
  for (int i = 0; i < 200; ++i) wi.row(i) = pairs[i].first.transpose(), wr.row(i) = pairs[i].second.transpose();
  std::mt19937_64 rng(29);
  std::normal_distribution<double> g(0.0, 1.0);
  HalfAngleFactors lobe = fitted_lobe("model:ggx:alpha=0.3");
  lobe.u = {lobe.u[0], lobe.u[0], lobe.u[0]};
  lobe.v = {lobe.v[0], 0.5 * lobe.v[0], 2.0 * lobe.v[0]};
  for (const int order : {1, 5, 6, kMaxPointModeOrder})
    for (const bool cosine : {false, true}) {
      Spectrum s;
      s.order = order;
      s.cosine = cosine;
      s.source = "random modes";
      const int m = hemisphere_basis_count(order);
      for (int c = 0; c < 3; ++c) {
        Eigen::MatrixXd C(m, m);
        for (Eigen::Index k = 0; k < C.size(); ++k) C.data()[k] = g(rng) / (1.0 + k % m + k / m);  // decaying
        C(0, 0) = 2.0;  // a positive body under the random terms
        s.channels.push_back(C);
      }
      for (const bool with_lobe : {false, true}) {
        const std::optional<HalfAngleFactors> l = with_lobe ? std::optional<HalfAngleFactors>(lobe) : std::nullopt;
        const RenderMaterial mat(s, l, coarse());
        const Eigen::MatrixXd b = evaluate_material(s, l, wi, wr);
        for (int i = 0; i < 200; ++i) {
          const MaterialColor<double> v = mat.eval(pairs[i].first, pairs[i].second);
          for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(v[c], b(i, c), kModesRelTol * (1 + std::abs(b(i, c))))
                << order << " " << cosine << " " << with_lobe << " " << i << " " << c;
        }
      }
    }
}

// Modes of order 0 (a constant, as a bank stores a paint's Lambertian part), alone and beside a lobe, are added
// without evaluating the basis: the values are those of the general path (the same modes written at order 1,
// with zero coefficients beyond C_00) and of the batch evaluation, the constant and the clamp max(0, .) included
// (a negative constant makes the sum negative at some pairs beside the lobe; modes alone are not clamped, as in
// the batch evaluation), with and without the cosine division.
TEST(RenderMaterial, ModesOfOrderZeroAreTheirConstantAloneAndBesideALobe) {
  const auto pairs = random_pairs(300, 12);
  RowMatrix3d wi(300, 3), wr(300, 3);
  for (int i = 0; i < 300; ++i) wi.row(i) = pairs[i].first.transpose(), wr.row(i) = pairs[i].second.transpose();
  const HalfAngleFactors& lobe = fitted_lobe("model:ggx:alpha=0.3");
  for (const bool with_lobe : {true, false})
    for (const bool cosine : {false, true})
      for (const double c00 : {0.2, -0.05}) {
        const std::optional<HalfAngleFactors> l = with_lobe ? std::optional<HalfAngleFactors>(lobe) : std::nullopt;
        Spectrum s0 = zero_spectrum(), s1 = zero_spectrum();
        s0.cosine = s1.cosine = cosine;
        s0.channels[0](0, 0) = c00;
        s1.order = 1;
        s1.channels = {Eigen::MatrixXd::Zero(3, 3)};
        s1.channels[0](0, 0) = c00;
        const RenderMaterial m0(s0, l, coarse()), m1(s1, l, coarse());
        const Eigen::MatrixXd b = evaluate_material(s0, l, wi, wr);
        int clamped = 0;
        for (int i = 0; i < 300; ++i) {
          const double v0 = m0.eval(pairs[i].first, pairs[i].second)[0], v1 = m1.eval(pairs[i].first, pairs[i].second)[0];
          EXPECT_NEAR(v0, v1, kModesRelTol * (1 + std::abs(v1))) << with_lobe << " " << cosine << " " << c00 << " " << i;
          EXPECT_NEAR(v0, b(i, 0), kModesRelTol * (1 + std::abs(b(i, 0)))) << with_lobe << " " << cosine << " " << c00 << " " << i;
          clamped += v0 == 0.0;
        }
        if (with_lobe && c00 < 0.0) {  // modes alone are not clamped, as in the batch evaluation
          EXPECT_GT(clamped, 0) << "the negative constant should clamp some pairs to 0";
        }
      }
}

TEST(RenderMaterial, EvalIsReciprocalAndFloatFormsRoundTheDoubleOnes) {
  const RenderMaterial lm = lobe_material("model:ggx:alpha=0.3", coarse());
  const RenderMaterial gm = RenderMaterial::open("model:0.4*lambert+0.6*ggx:alpha=0.2", coarse());
  for (const auto& [a, b] : random_pairs(200, 12)) {
    EXPECT_EQ(lm.eval(a, b)[0], lm.eval(b, a)[0]);  // lobes are bitwise reciprocal
    const double g = gm.eval(a, b)[0];
    EXPECT_NEAR(g, gm.eval(b, a)[0], kKernelRelTol * g);
    const Eigen::Vector3f af = a.cast<float>(), bf = b.cast<float>();
    const double gd = gm.eval(Eigen::Vector3d(af.cast<double>()), Eigen::Vector3d(bf.cast<double>()))[0];
    EXPECT_NEAR(gm.eval(af, bf)[0], gd, kFloatRelTol * gd);
    const double pd = gm.pdf(Eigen::Vector3d(af.cast<double>()), Eigen::Vector3d(bf.cast<double>()));
    EXPECT_NEAR(gm.pdf(af, bf), pd, kFloatRelTol * pd);
  }
  // A float draw is the double draw of the same numbers, rounded.
  const Eigen::Vector3f wi = direction_from_angles(0.7, 0.3).cast<float>();
  const MaterialSample<float> f = gm.sample(wi, 0.3f, 0.6f);
  const MaterialSample<double> d = gm.sample(Eigen::Vector3d(wi.cast<double>()), static_cast<double>(0.3f), static_cast<double>(0.6f));
  ASSERT_TRUE(f.valid() && d.valid());
  EXPECT_NEAR(f.weight[0], d.weight[0], kFloatRelTol * d.weight[0]);
  EXPECT_NEAR(f.pdf, d.pdf, kFloatRelTol * d.pdf);
  EXPECT_EQ(f.flags, d.flags);
}

// Draws of every representation follow pdf() (chi-squared), and pdf() is what sample() reports.
TEST(RenderMaterial, DrawsFollowThePdfForEveryRepresentation) {
  std::vector<std::pair<std::string, std::shared_ptr<RenderMaterial>>> cases;
  for (const std::string spec : {"model:lambert", "model:ggx:alpha=0.3", "model:ggx-aniso:alpha_x=0.1,alpha_y=0.4,azimuth=30",
                                 "model:beckmann:alpha=0.2", "model:0.4*lambert+0.6*ggx:alpha=0.2"})
    cases.push_back({spec, std::make_shared<RenderMaterial>(RenderMaterial::open(spec, coarse()))});
  RenderMaterialOptions vndf = coarse();
  vndf.visible_normals = true;
  cases.push_back({"ggx visible normals", std::make_shared<RenderMaterial>(RenderMaterial::open("model:0.4*lambert+0.6*ggx:alpha=0.2", vndf))});
  cases.push_back({"half-angle lobe", std::make_shared<RenderMaterial>(lobe_material("model:ggx:alpha=0.3", coarse()))});
  cases.push_back({"modes", std::make_shared<RenderMaterial>(minnaert_spectrum(3), std::nullopt, coarse())});
  cases.push_back({"hybrid", std::make_shared<RenderMaterial>(minnaert_spectrum(2), fitted_lobe("model:ggx:alpha=0.3"), coarse())});
  constexpr int kDraws = 20000;
  for (const auto& [name, m] : cases)
    for (const double theta_deg : {10.0, 60.0}) {
      const Eigen::Vector3d wi = direction_from_angles(theta_deg * M_PI / 180, 0.4);
      std::mt19937_64 rng(21);
      std::uniform_real_distribution<double> u(0.0, 1.0);
      std::vector<Eigen::Vector3d> draws;
      for (int i = 0; i < kDraws; ++i) {
        const MaterialSample<double> s = m->sample(wi, u(rng), u(rng));
        if (!s.valid()) continue;
        draws.push_back(s.wr);
        EXPECT_NEAR(s.pdf, m->pdf(wi, s.wr), kPdfRoundTripRelTol * s.pdf) << name;
      }
      // C++17 lambdas cannot capture a structured binding (clang refuses): the material through a plain pointer.
      const auto* material = &*m;
      const auto density = [&](const RowMatrix3d& w) {
        Eigen::VectorXd p(w.rows());
        for (Eigen::Index i = 0; i < w.rows(); ++i) p[i] = material->pdf(wi, w.row(i).transpose());
        return p;
      };
      // The density over the upper hemisphere integrates to the probability of a valid draw.
      const auto whole = test_support::chi_square_directions(draws, density, 20, 40, 6);
      const double valid = static_cast<double>(draws.size()) / kDraws;
      EXPECT_NEAR(valid, whole.expected_total, kStandardErrors * std::sqrt(valid * (1 - valid) / kDraws) + 2e-3) << name << " " << theta_deg;
      const auto r = test_support::chi_square_directions(
          draws, [&](const RowMatrix3d& w) { return Eigen::VectorXd(density(w) / whole.expected_total); }, 20, 40, 6);
      EXPECT_GT(r.p_value, kSignificance) << name << " at " << theta_deg << ": chi2 " << r.chi2 << ", dof " << r.dof;
    }
}

// An isotropic material's tables store only the half-vector bins of phi_h >= 0 and draw the mirror image
// (HalfVectorTableOptions::mirror): its density and albedo are those of the full tables. The masses of a cell
// and of its image are the same sums over mirror-image points of an isotropic f; what differs is rounding:
// the masses in float (6e-8), and an int16 slope whose rounding tie goes the other way moves the density by
// up to 1 / 32000 of its mean (3e-5).
constexpr double kMirrorRelTol = 1e-4;
TEST(RenderMaterial, MirroredTablesHaveTheDensityOfFullOnes) {
  RenderMaterialOptions full = coarse();
  full.table.mirror = false;
  for (const std::string spec : {"model:0.4*lambert+0.6*ggx:alpha=0.2", "lobe"}) {
    const RenderMaterial m = spec == "lobe" ? lobe_material("model:ggx:alpha=0.3", coarse()) : RenderMaterial::open(spec, coarse());
    const RenderMaterial f = spec == "lobe" ? lobe_material("model:ggx:alpha=0.3", full) : RenderMaterial::open(spec, full);
    int compared = 0;
    for (const auto& [wi, wr] : random_pairs(2000, 43)) {
      const double p = f.pdf(wi, wr);
      EXPECT_NEAR(m.pdf(wi, wr), p, kMirrorRelTol * p) << spec;
      EXPECT_NEAR(m.albedo_estimate(wi), f.albedo_estimate(wi), kMirrorRelTol * f.albedo_estimate(wi)) << spec;
      compared += p > 0.0;
    }
    EXPECT_GT(compared, 1900) << spec;  // nearly every pair has density (the floor covers reflected directions)
  }
}

// The mean weight is the directional albedo (white furnace per incident direction), against an independent
// Gauss-Legendre quadrature of f cos.
TEST(RenderMaterial, MeanWeightIsTheDirectionalAlbedo) {
  std::vector<std::pair<std::string, std::shared_ptr<RenderMaterial>>> cases;
  for (const std::string spec : {"model:lambert", "model:ggx:alpha=0.3", "model:0.4*lambert+0.6*ggx:alpha=0.2", "model:beckmann:alpha=0.2"})
    cases.push_back({spec, std::make_shared<RenderMaterial>(RenderMaterial::open(spec, coarse()))});
  cases.push_back({"half-angle lobe", std::make_shared<RenderMaterial>(lobe_material("model:ggx:alpha=0.3", coarse()))});
  cases.push_back({"hybrid", std::make_shared<RenderMaterial>(minnaert_spectrum(2), fitted_lobe("model:ggx:alpha=0.3"), coarse())});
  for (const auto& [name, m] : cases)
    for (const double theta_deg : {0.0, 45.0, 80.0}) {
      const Eigen::Vector3d wi = direction_from_angles(theta_deg * M_PI / 180, 1.1);
      const double a = albedo_by_quadrature(*m, wi);
      const WeightStats w = weight_stats(*m, wi, 20000, 31);
      EXPECT_NEAR(w.mean, a, kStandardErrors * w.sd / std::sqrt(20000.0) + 1e-4 * a) << name << " at " << theta_deg;
    }
}

// The example's tables (12 incident nodes, 64 x 64 half-vector cells) at normal incidence, where the horizon
// of w_r lies at theta_h = 45 degrees: the sub-cell centres of the ring of cells across it all reflect below
// the horizon, while w_r from 89 to 90 degrees above it holds 3e-4 of a Lambertian albedo (sin^2 of 1 degree).
RenderMaterialOptions example_tables() { return tables(12, 64); }

// Near the horizon the weight f cos / pdf stays within a small factor of the albedo: a cell drawn by the
// tables' floor alone (kHalfVectorFloor of the mean mass) gives weights over 100 x the albedo, which a
// white furnace of 1e5-1e6 draws then misses in its typical value (the estimate came out 2e-4 low).
TEST(RenderMaterial, WeightsNearTheHorizonStayBounded) {
  // Measured at most 12 (theta_i 30 deg, between nodes; 4 at normal incidence); a cell held only by the
  // floor gives a factor of 100 or more, a density reaching 0 at a cell's edge 1e3 to 1e6.
  constexpr double kMaxWeightOverAlbedo = 20.0;
  for (const std::string spec : {"model:lambert", "model:0.4*lambert+0.6*ggx:alpha=0.2"}) {
    const RenderMaterial m = RenderMaterial::open(spec, example_tables());
    for (const double theta_i_deg : {0.0, 30.0, 45.0, 60.0, 75.0}) {
      const Eigen::Vector3d wi = direction_from_angles(theta_i_deg * M_PI / 180, 0.0);
      const double albedo = albedo_by_quadrature(m, wi);
      double worst = 0.0, worst_theta = 0.0;
      for (int a = 0; a < 200; ++a)
        for (int b = 0; b < 90; ++b) {
          const double theta_r = (80.0 + 9.99 * (a + 0.5) / 200) * M_PI / 180, phi_r = 2 * M_PI * (b + 0.5) / 90;
          const Eigen::Vector3d wr = direction_from_angles(theta_r, phi_r);
          const double p = m.pdf(wi, wr), fc = m.eval(wi, wr)[0] * wr.z();
          ASSERT_GT(p, 0.0) << spec << " at theta_i " << theta_i_deg << ", theta_r " << theta_r * 180 / M_PI;
          if (fc / p > worst) worst = fc / p, worst_theta = theta_r * 180 / M_PI;
        }
      EXPECT_LE(worst / albedo, kMaxWeightOverAlbedo) << spec << " at theta_i " << theta_i_deg << ": worst at theta_r " << worst_theta;
    }
  }
}

// The white furnace at normal incidence to 1e-4 relative: the mean weight of 400,000 draws against the albedo
// by quadrature (the example's check, with draws enough to resolve the 3e-4 a sliver at the horizon holds).
TEST(RenderMaterial, FurnaceAtNormalIncidenceResolvesTheHorizon) {
  // 4 standard errors: a false failure has probability 6e-5 for a normal mean.
  constexpr double kFurnaceStandardErrors = 4.0;
  constexpr int kDraws = 400000;
  const RenderMaterial m = RenderMaterial::open("model:lambert", example_tables());
  const Eigen::Vector3d wi(0, 0, 1);
  const double a = albedo_by_quadrature(m, wi);
  const WeightStats w = weight_stats(m, wi, kDraws, 71);
  const double se = w.sd / std::sqrt(static_cast<double>(kDraws));
  EXPECT_LT(se, 1e-4 * a);  // the check resolves 1e-4 relative
  EXPECT_NEAR(w.mean, a, kFurnaceStandardErrors * se) << "standard error " << se;
}

// The targets: relative standard deviation of f cos / pdf for GGX lobes, models and bank lobes alike.
TEST(RenderMaterial, WeightsOfGgxLobesSpreadLittle) {
  for (const double alpha : {0.05, 0.3}) {
    const std::string spec = "model:ggx:alpha=" + std::to_string(alpha);
    RenderMaterialOptions vndf;
    vndf.visible_normals = true;
    const RenderMaterial mm = RenderMaterial::open(spec), lm = lobe_material(spec), vm = RenderMaterial::open(spec, vndf);
    for (const double theta_deg : {0.0, 45.0, 75.0}) {
      const Eigen::Vector3d wi = direction_from_angles(theta_deg * M_PI / 180, 0.2);
      for (const RenderMaterial* m : {&mm, &lm, &vm}) {
        const WeightStats w = weight_stats(*m, wi, 10000, 41);
        const char* name = m == &mm ? "model" : m == &lm ? "lobe" : "visible normals";
        std::printf("alpha %.2f theta %2.0f %-16s rsd %.4f (valid %.4f)\n", alpha, theta_deg, name, w.sd / w.mean, w.valid / 10000.0);
        if (m == &vm) continue;  // reported only: its draws below the horizon (8 % at alpha 0.3) are zeros
        const double bound = alpha < 0.1 ? kRsdNarrow : kRsdWide;
        EXPECT_LE(w.sd / w.mean, bound) << spec << " " << name << " at " << theta_deg;
      }
    }
  }
}

// Several threads sharing one material get, call for call, the values one thread gets (the material's state
// is read-only after construction). Built with -fsanitize=thread (docs/reliability.md, "ThreadSanitizer") this
// test is where a data race in eval / pdf / sample would be reported.
TEST(RenderMaterial, ThreadsSharingOneMaterialGetTheValuesOfOneThread) {
  constexpr int kThreads = 4, kCalls = 2000;
  const RenderMaterial lm = lobe_material("model:ggx:alpha=0.3", coarse());
  const RenderMaterial mm = RenderMaterial::open("model:0.5*lambert+0.3*ggx:alpha=0.2+0.2*mirror", coarse());
  const auto pairs = random_pairs(kCalls, 61);
  for (const RenderMaterial* m : {&lm, &mm}) {
    // One thread's values: f, pdf, and the draw (w_r.x, weight, pdf) per input; then each thread's.
    const auto run = [&](std::vector<double>& out) {
      out.clear();
      for (int i = 0; i < kCalls; ++i) {
        const auto& [wi, wr] = pairs[static_cast<size_t>(i)];
        const MaterialSample<double> s = m->sample(wi, (i + 0.5) / kCalls, wr.z());
        const MaterialSample<float> sf = m->sample(Eigen::Vector3f(wi.cast<float>()), static_cast<float>((i + 0.5) / kCalls), static_cast<float>(wr.z()));
        out.insert(out.end(), {m->eval(wi, wr)[0], m->pdf(wi, wr), s.wr.x(), s.weight[0], s.pdf,
                               static_cast<double>(m->eval(Eigen::Vector3f(wi.cast<float>()), Eigen::Vector3f(wr.cast<float>()))[0]),
                               static_cast<double>(sf.pdf)});
      }
    };
    std::vector<double> one;
    run(one);
    std::vector<std::vector<double>> each(kThreads);
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t) threads.emplace_back(run, std::ref(each[static_cast<size_t>(t)]));
    for (std::thread& t : threads) t.join();
    for (int t = 0; t < kThreads; ++t) EXPECT_EQ(each[static_cast<size_t>(t)], one) << m->spec() << " thread " << t;
  }
}

TEST(RenderMaterial, DeltaPartsAreSampledAndFlagged) {
  // 0.5 lambert + 0.5 mirror: albedos 0.5 and 0.5, so half the draws are the mirror, each of weight 0.5 / 0.5.
  const RenderMaterial m = RenderMaterial::open("model:0.5*lambert+0.5*mirror");
  EXPECT_EQ(m.flags(), kMaterialReflection | kMaterialDiffuse | kMaterialSpecular);
  const Eigen::Vector3d wi = direction_from_angles(0.6, 0.9);
  std::mt19937_64 rng(51);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  constexpr int n = 20000;
  int mirror = 0;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const MaterialSample<double> s = m.sample(wi, u(rng), u(rng));
    if (s.is_specular()) {
      ++mirror;
      EXPECT_NEAR((s.wr - Eigen::Vector3d(-wi.x(), -wi.y(), wi.z())).norm(), 0.0, 1e-15);
      EXPECT_NEAR(s.weight[0] * s.pdf, 0.5, 1e-12);
      EXPECT_EQ(m.pdf(wi, s.wr), m.pdf(wi, s.wr));  // the regular density only (finite)
    } else if (s.valid()) {  // a table draw may fall below the horizon (a zero of the estimator)
      EXPECT_EQ(s.flags, kMaterialReflection | kMaterialDiffuse);
    }
    sum += s.weight[0];
  }
  // Lambert's table albedo is an estimate of 1 (the tables' midpoint rule): the delta share is 0.5 / (0.5 + a).
  const double share = 0.5 / m.albedo_estimate(wi);
  EXPECT_NEAR(static_cast<double>(mirror) / n, share, kStandardErrors * std::sqrt(share * (1 - share) / n));
  EXPECT_NEAR(sum / n, 1.0, kStandardErrors * 0.5 / std::sqrt(n));  // weights 1 (mirror) and ~1 (Lambert)
  // A mirror alone: every draw is the delta.
  const RenderMaterial mirror_only = RenderMaterial::open("model:mirror");
  const MaterialSample<double> s = mirror_only.sample(wi, 0.3, 0.7);
  EXPECT_TRUE(s.is_specular());
  EXPECT_EQ(s.weight[0], 1.0);
  EXPECT_EQ(mirror_only.eval(wi, s.wr)[0], 0.0);
}

TEST(RenderMaterial, BelowTheHorizonThereIsNothing) {
  const RenderMaterial m = RenderMaterial::open("model:ggx:alpha=0.3");
  const Eigen::Vector3d up(0, 0, 1), down(0.6, 0, -0.8);
  EXPECT_EQ(m.eval(up, down)[0], 0.0);
  EXPECT_EQ(m.eval(down, up)[0], 0.0);
  EXPECT_EQ(m.pdf(up, down), 0.0);
  EXPECT_FALSE(m.sample(down, 0.5, 0.5).valid());
  EXPECT_FALSE(m.sample(Eigen::Vector3d(NAN, 0, 1), 0.5, 0.5).valid());
}

TEST(RenderMaterial, RefusesTooManyChannelsAndHighModeOrders) {
  Spectrum s = minnaert_spectrum(2);
  s.order = kMaxPointModeOrder + 2;
  const int mm = (s.order + 1) * (s.order + 2) / 2;
  s.channels = {Eigen::MatrixXd::Identity(mm, mm)};
  EXPECT_THROW(RenderMaterial(s, std::nullopt), ArgumentError);
  // Coefficients whose shape is not the order's count x count (per-sample code reads them as that), in any
  // channel: a one-line error naming the channel and both shapes.
  Spectrum bad = zero_spectrum();
  bad.channels = {Eigen::MatrixXd::Constant(1, 1, 0.2), Eigen::MatrixXd()};
  try {
    RenderMaterial m(bad, fitted_lobe("model:ggx:alpha=0.3"));
    ADD_FAILURE() << "an empty channel beside modes was accepted";
  } catch (const ArgumentError& e) {
    EXPECT_NE(std::string(e.what()).find("channel 1 are 0 x 0, expected 1 x 1 for order 0"), std::string::npos) << e.what();
  }
  bad = minnaert_spectrum(2);
  bad.channels[0].conservativeResize(bad.channels[0].rows() - 1, bad.channels[0].cols());
  EXPECT_THROW(RenderMaterial(bad, std::nullopt), ArgumentError);
}

}  // namespace ICOBRDF_UNITY_ID
