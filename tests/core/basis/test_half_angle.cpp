// Half-angle coordinates: round trips (including h = n, grazing, w_i = w_r, normal incidence and the
// degenerate opposite horizon pair), the swap map, reciprocity and isotropy of models in these coordinates,
// and the measure dw_i dw_r = 4 cos(theta_d) dw_h dw_d.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <random>
#include <vector>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/basis/half_angle.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "tests/core/brdf_quadrature.hpp"
#include "tests/support/unity_id.hpp"

using namespace icobrdf;

namespace ICOBRDF_UNITY_ID {
// Round trips: a few roundings per component (normalization, one rotation there and back).
constexpr double kRoundTripTol = 1e-14;
// Model values at a pair and at its swapped/rotated image built by different arithmetic: rounding of the
// directions (~1e-16) times the model's relative slope, far below this for the smooth lobes used.
constexpr double kModelTol = 1e-12;
// Gauss-Legendre quadrature of smooth trigonometric polynomials: rounding only (converged in the node count).
constexpr double kQuadratureTol = 1e-12;

// Unit vectors are unit only to rounding; (h, d) with |d| = 1 cannot carry |w_i|^2 - |w_r|^2 ~ 2 eps, and
// the round trip loses it divided by |w_i + w_r| (header): a tolerance of 4 eps / |w_i + w_r| on top.
void expect_round_trip(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) {
  const double kRoundTripTol = ::kRoundTripTol + 4 * DBL_EPSILON / std::max((wi + wr).norm(), 1e-300);
  // Through the vectors (h, d) and through the angles.
  Eigen::Vector3d h, d, a, b;
  half_diff_from_pair(wi, wr, h, d);
  EXPECT_NEAR(h.norm(), 1.0, kRoundTripTol);
  EXPECT_NEAR(d.norm(), 1.0, kRoundTripTol);
  pair_from_half_diff(h, d, a, b);
  EXPECT_LT((a - wi).cwiseAbs().maxCoeff(), kRoundTripTol) << wi.transpose() << " | " << wr.transpose();
  EXPECT_LT((b - wr).cwiseAbs().maxCoeff(), kRoundTripTol) << wi.transpose() << " | " << wr.transpose();
  const HalfAngleCoords c = half_angle_from_pair(wi, wr);
  for (double x : {c.theta_h, c.phi_h, c.theta_d, c.phi_d}) EXPECT_TRUE(std::isfinite(x));
  pair_from_half_angle(c, a, b);
  EXPECT_LT((a - wi).cwiseAbs().maxCoeff(), kRoundTripTol) << wi.transpose() << " | " << wr.transpose();
  EXPECT_LT((b - wr).cwiseAbs().maxCoeff(), kRoundTripTol) << wi.transpose() << " | " << wr.transpose();
}

Eigen::Vector3d dir_deg(double theta, double phi) { return direction_from_angles(theta * M_PI / 180, phi * M_PI / 180); }

TEST(HalfAngle, RoundTripRandomPairs) {
  std::mt19937_64 rng(11);
  for (int k = 0; k < 20000; ++k) {
    const Eigen::Vector3d wi = uniform_direction(rng), wr = uniform_direction(rng);
    expect_round_trip(wi, wr);
  }
}

TEST(HalfAngle, RoundTripSpecialPairs) {
  std::mt19937_64 rng(12);
  for (int k = 0; k < 200; ++k) {
    const Eigen::Vector3d w = uniform_direction(rng);
    expect_round_trip(w, mirror_direction(w));  // h = n exactly
    expect_round_trip(w, w);                    // w_i = w_r: d is the pole
    const Eigen::Vector3d g = uniform_direction(rng, 0.0, 0.0), g2 = uniform_direction(rng, 0.0, 0.0);
    expect_round_trip(g, g2);  // both grazing
    expect_round_trip(g, w);   // one grazing
    expect_round_trip(Eigen::Vector3d(0, 0, 1), w);  // normal incidence
  }
  expect_round_trip(Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 0, 1));
  // Nearly opposite horizon directions: h is horizontal, the round trip holds to the tolerance above.
  expect_round_trip(dir_deg(90, 10), dir_deg(90, 190.0 + 1e-9));
  expect_round_trip(dir_deg(89.9, 10), dir_deg(90, 190.0 + 1e-3));
}

TEST(HalfAngle, MirrorPairHasHAtTheNormalWithPhiHZero) {
  const Eigen::Vector3d wi = dir_deg(40, 70);
  const HalfAngleCoords c = half_angle_from_pair(wi, mirror_direction(wi));
  EXPECT_EQ(c.theta_h, 0.0);
  EXPECT_EQ(c.phi_h, 0.0);
  EXPECT_NEAR(c.theta_d, 40 * M_PI / 180, kRoundTripTol);
  EXPECT_NEAR(c.phi_d, 70 * M_PI / 180, kRoundTripTol);  // d = w_i in the unrotated frame
}

TEST(HalfAngle, OppositeHorizonPairUsesTheFallback) {
  const Eigen::Vector3d wi = dir_deg(90, 30), wr = -wi;
  Eigen::Vector3d h, d, a, b;
  half_diff_from_pair(wi, wr, h, d);
  EXPECT_EQ(h, Eigen::Vector3d(0, 0, 1));
  EXPECT_LT((d - wi).cwiseAbs().maxCoeff(), kRoundTripTol);
  pair_from_half_diff(h, d, a, b);
  EXPECT_LT((a - wi).cwiseAbs().maxCoeff(), kRoundTripTol);
  EXPECT_LT((b - wr).cwiseAbs().maxCoeff(), kRoundTripTol);
  const HalfAngleCoords c = half_angle_from_pair(wi, wr);
  EXPECT_EQ(c.theta_h, 0.0);
  EXPECT_NEAR(c.theta_d, M_PI / 2, kRoundTripTol);
}

TEST(HalfAngle, SwapLeavesHAndNegatesDxDy) {
  std::mt19937_64 rng(13);
  for (int k = 0; k < 2000; ++k) {
    const Eigen::Vector3d wi = uniform_direction(rng), wr = uniform_direction(rng);
    Eigen::Vector3d h1, d1, h2, d2;
    half_diff_from_pair(wi, wr, h1, d1);
    half_diff_from_pair(wr, wi, h2, d2);
    // s = w_i + w_r is the same sum and m = w_i - w_r is negated exactly, so the map is bitwise.
    EXPECT_EQ(h1, h2);
    EXPECT_EQ(d2, Eigen::Vector3d(-d1.x(), -d1.y(), d1.z()));
    const HalfAngleCoords a = half_angle_from_pair(wi, wr), b = half_angle_from_pair(wr, wi);
    EXPECT_EQ(a.theta_h, b.theta_h);
    EXPECT_EQ(a.phi_h, b.phi_h);
    EXPECT_EQ(a.theta_d, b.theta_d);
    EXPECT_NEAR(std::remainder(b.phi_d - a.phi_d - M_PI, 2 * M_PI), 0.0, kRoundTripTol);
  }
}

TEST(HalfAngle, DefinitionByRotationsAndMirror) {
  // d = Ry(-theta_h) Rz(-phi_h) w_i with explicit rotation matrices, and w_r = 2 (w_i . h) h - w_i.
  std::mt19937_64 rng(14);
  for (int k = 0; k < 500; ++k) {
    const Eigen::Vector3d wi = uniform_direction(rng), wr = uniform_direction(rng);
    const Eigen::Vector3d h = (wi + wr).normalized();
    const double th = std::atan2(std::hypot(h.x(), h.y()), h.z()), ph = std::atan2(h.y(), h.x());
    const Eigen::Matrix3d rz = Eigen::AngleAxisd(-ph, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const Eigen::Matrix3d ry = Eigen::AngleAxisd(-th, Eigen::Vector3d::UnitY()).toRotationMatrix();
    const Eigen::Vector3d d_ref = ry * rz * wi;
    Eigen::Vector3d h2, d;
    half_diff_from_pair(wi, wr, h2, d);
    EXPECT_LT((h2 - h).cwiseAbs().maxCoeff(), kRoundTripTol);
    EXPECT_LT((d - d_ref).cwiseAbs().maxCoeff(), kRoundTripTol);
    EXPECT_LT((2 * wi.dot(h) * h - wi - wr).cwiseAbs().maxCoeff(), kRoundTripTol);
    // Lambert in half-angle coordinates (the rank-2 identity of the header).
    const HalfAngleCoords c = half_angle_from_pair(wi, wr);
    const double lam = std::pow(std::cos(c.theta_d) * std::cos(c.theta_h), 2) -
                       std::pow(std::sin(c.theta_d) * std::cos(c.phi_d) * std::sin(c.theta_h), 2);
    EXPECT_NEAR(lam, wi.z() * wr.z(), kRoundTripTol);
  }
}

TEST(HalfAngle, ReciprocalModelIsPiPeriodicInPhiD) {
  const auto ggx = parse_model_source("model:ggx:alpha=0.1,f0=0.04");
  const auto aniso = parse_model_source("model:ggx-aniso:alpha_x=0.1,alpha_y=0.3,azimuth=20");
  std::mt19937_64 rng(15);
  std::uniform_real_distribution<double> th(0.0, M_PI / 2), ph(-M_PI, M_PI);
  int tested = 0;
  while (tested < 2000) {
    const HalfAngleCoords c{0.5 * th(rng), ph(rng), th(rng), ph(rng)};
    Eigen::Vector3d wi, wr, wi2, wr2;
    pair_from_half_angle(c, wi, wr);
    pair_from_half_angle({c.theta_h, c.phi_h, c.theta_d, c.phi_d + M_PI}, wi2, wr2);
    if (wi.z() <= 0.0 || wr.z() <= 0.0) continue;
    ++tested;
    for (const auto* m : {ggx.get(), aniso.get()}) {
      const double f = m->eval(wi, wr), g = m->eval(wi2, wr2);
      EXPECT_LE(std::abs(f - g), kModelTol * std::abs(f)) << m->spec();
    }
  }
}

TEST(HalfAngle, IsotropicModelDoesNotDependOnPhiH) {
  const auto ggx = parse_model_source("model:ggx:alpha=0.2,f0=0.04");
  const auto aniso = parse_model_source("model:ggx-aniso:alpha_x=0.1,alpha_y=0.3");
  std::mt19937_64 rng(16);
  std::uniform_real_distribution<double> th(0.0, M_PI / 2), ph(-M_PI, M_PI);
  int tested = 0;
  double aniso_spread = 0.0;
  while (tested < 500) {
    const HalfAngleCoords c{0.5 * th(rng), 0.0, 0.5 * th(rng), ph(rng)};
    Eigen::Vector3d wi, wr;
    pair_from_half_angle(c, wi, wr);
    if (wi.z() <= 0.0 || wr.z() <= 0.0) continue;
    ++tested;
    const double f0 = ggx->eval(wi, wr), a0 = aniso->eval(wi, wr);
    for (double phi_h : {0.3, 1.7, -2.9}) {
      pair_from_half_angle({c.theta_h, phi_h, c.theta_d, c.phi_d}, wi, wr);
      EXPECT_LE(std::abs(ggx->eval(wi, wr) - f0), kModelTol * f0);
      aniso_spread = std::max(aniso_spread, std::abs(aniso->eval(wi, wr) - a0) / a0);
    }
  }
  EXPECT_GT(aniso_spread, 0.1);  // the check can tell: the anisotropic lobe does depend on phi_h
}

TEST(HalfAngle, MeasureIsFourCosThetaD) {
  // integral over S^2 x S^2 of g(w_i, w_r) dw_i dw_r = integral over h in S^2, d in the upper hemisphere of
  // 4 cos(theta_d) g dw_h dw_d, with (w_i, w_r) from the inverse map. Closed forms on S^2:
  // int x^2 = 4 pi/3, int x^4 = 4 pi/5, int x^2 y^2 = 4 pi/15; int int (w_i . w_r)^2 = (4 pi)^2 / 3.
  const auto rule = [](int n, double lo, double hi) {
    const test::GaussRule g = test::gauss_legendre_gw(n);
    std::vector<std::pair<double, double>> r;
    for (std::size_t k = 0; k < g.x.size(); ++k)
      r.emplace_back(0.5 * (lo + hi) + 0.5 * (hi - lo) * g.x[k], 0.5 * (hi - lo) * g.w[k]);
    return r;
  };
  const auto th_h = rule(40, 0.0, M_PI), th_d = rule(24, 0.0, M_PI / 2);
  const int nphi = 24;
  const Eigen::Vector3d a = Eigen::Vector3d(1, 2, 2) / 3.0, b = Eigen::Vector3d(0, 0.6, 0.8);
  double i1 = 0, i2 = 0, i3 = 0;
  for (const auto& [t1, w1] : th_h)
    for (int p1 = 0; p1 < nphi; ++p1)
      for (const auto& [t2, w2] : th_d)
        for (int p2 = 0; p2 < nphi; ++p2) {
          const double ph = 2 * M_PI * (p1 + 0.25) / nphi, pd = 2 * M_PI * (p2 + 0.5) / nphi;
          const double w = w1 * std::sin(t1) * (2 * M_PI / nphi) * w2 * std::sin(t2) * (2 * M_PI / nphi) * 4 * std::cos(t2);
          Eigen::Vector3d wi, wr;
          pair_from_half_angle({t1, ph, t2, pd}, wi, wr);
          i1 += w * std::pow(wi.dot(a), 2) * std::pow(wr.dot(b), 4);
          i2 += w * std::pow(wi.x() * wr.y(), 2);
          i3 += w * std::pow(wi.dot(wr), 2);
        }
  const double s2 = 4 * M_PI;
  EXPECT_NEAR(i1 / (s2 / 3 * s2 / 5), 1.0, kQuadratureTol);
  EXPECT_NEAR(i2 / (s2 / 3 * s2 / 3), 1.0, kQuadratureTol);
  EXPECT_NEAR(i3 / (s2 * s2 / 3), 1.0, kQuadratureTol);
}

TEST(HalfAngle, MeasureOfPairsAboveTheHorizonByMonteCarlo) {
  // Pairs on or above the horizon: measure (2 pi)^2, and int cos_i cos_r = pi^2. Sampling h and d uniformly
  // on upper hemispheres (h_z >= 0 for every such pair) with weight 4 cos(theta_d) (2 pi)^2.
  std::mt19937_64 rng(17);
  const int n = 400000;
  double s0 = 0, s0sq = 0, s1 = 0, s1sq = 0;
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d h = uniform_direction(rng), d = uniform_direction(rng);
    Eigen::Vector3d wi, wr;
    pair_from_half_diff(h, d, wi, wr);
    if (wi.z() < 0 || wr.z() < 0) continue;
    const double w = 4 * d.z() * 4 * M_PI * M_PI;
    s0 += w, s0sq += w * w;
    s1 += w * wi.z() * wr.z(), s1sq += std::pow(w * wi.z() * wr.z(), 2);
  }
  // Tolerance: 5 standard errors of the mean, measured from the samples themselves.
  const auto check = [&](double s, double ssq, double expected) {
    const double mean = s / n, se = std::sqrt((ssq / n - mean * mean) / n);
    EXPECT_NEAR(mean, expected, 5 * se);
    EXPECT_LT(se, 0.01 * expected);  // the check is sharp enough to mean something
  };
  check(s0, s0sq, 4 * M_PI * M_PI);
  check(s1, s1sq, M_PI * M_PI);
}

TEST(HalfAngle, BatchFormsMatchScalarForms) {
  std::mt19937_64 rng(18);
  RowMatrix3d wi(100, 3), wr(100, 3);
  for (int k = 0; k < 100; ++k) wi.row(k) = uniform_direction(rng).transpose(), wr.row(k) = uniform_direction(rng).transpose();
  RowMatrix3d h, d, a, b;
  half_diff_from_pairs(wi, wr, h, d);
  pairs_from_half_diff(h, d, a, b);
  EXPECT_LT((a - wi).cwiseAbs().maxCoeff(), kRoundTripTol);
  EXPECT_LT((b - wr).cwiseAbs().maxCoeff(), kRoundTripTol);
  const HalfAngleMatrix ang = half_angles_from_pairs(wi, wr);
  pairs_from_half_angles(ang, a, b);
  EXPECT_LT((a - wi).cwiseAbs().maxCoeff(), kRoundTripTol);
  EXPECT_LT((b - wr).cwiseAbs().maxCoeff(), kRoundTripTol);
  const HalfAngleCoords c = half_angle_from_pair(wi.row(7).transpose(), wr.row(7).transpose());
  EXPECT_EQ(ang(7, 0), c.theta_h);
  EXPECT_EQ(ang(7, 3), c.phi_d);
  EXPECT_THROW(half_diff_from_pairs(wi, wr.topRows(5), h, d), std::invalid_argument);
}

}  // namespace ICOBRDF_UNITY_ID
