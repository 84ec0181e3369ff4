#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "icobrdf/core/basis/direction.hpp"

// Round trips through sin/cos/atan2 lose a few ulps; 1e-14 is ~50 ulps of pi.
constexpr double kRoundTripTol = 1e-14;

TEST(Direction, AnglesRoundTrip) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> th(0.0, M_PI / 2), ph(-M_PI, M_PI);
  for (int k = 0; k < 1000; ++k) {
    const double t = th(rng), p = ph(rng);
    const auto d = icobrdf::direction_from_angles(t, p);
    EXPECT_NEAR(d.norm(), 1.0, kRoundTripTol);
    const auto a = icobrdf::angles_from_direction(d);
    EXPECT_NEAR(a.theta, t, kRoundTripTol);
    EXPECT_NEAR(a.phi, p, kRoundTripTol);
  }
}

TEST(Direction, PoleEquatorAndMirror) {
  const auto pole = icobrdf::angles_from_direction({0, 0, 1});
  EXPECT_EQ(pole.theta, 0.0);
  EXPECT_EQ(pole.phi, 0.0);
  EXPECT_NEAR(icobrdf::angles_from_direction({0, 1, 0}).theta, M_PI / 2, kRoundTripTol);
  // The mirror direction of (theta, phi) is (theta, phi + pi).
  const auto d = icobrdf::direction_from_angles(0.3, 0.4);
  const auto m = icobrdf::angles_from_direction(icobrdf::mirror_direction(d));
  EXPECT_NEAR(m.theta, 0.3, kRoundTripTol);
  EXPECT_NEAR(m.phi, 0.4 - M_PI, kRoundTripTol);
}

// uniform_direction: unit vectors in the band, the azimuth drawn before z (pinned against two canonical
// draws of an equally seeded generator, so banks keep their held-out pairs), and uniform in solid angle:
// z uniform in [z_lo, z_hi] (mean (z_lo + z_hi)/2, variance (z_hi - z_lo)^2/12) and x, y of mean 0.
TEST(UniformDirection, BandOrderAndMoments) {
  // Statistical bound: 5 standard errors of a mean over kDraws samples (false alarm ~6e-7 per check).
  constexpr int kDraws = 200000;
  constexpr double kSigmas = 5.0;
  // acos, then cos and sin of the angles: a few ulps.
  constexpr double kUnitTol = 4e-15;
  const double z_lo = 0.25, z_hi = 0.75;
  std::mt19937_64 rng(11), twin(11);
  double sz = 0, sx = 0, sy = 0;
  for (int k = 0; k < kDraws; ++k) {
    const Eigen::Vector3d d = icobrdf::uniform_direction(rng, z_lo, z_hi);
    if (k < 100) {
      const double c1 = std::generate_canonical<double, 53>(twin), c2 = std::generate_canonical<double, 53>(twin);
      const Eigen::Vector3d e = icobrdf::direction_from_angles(std::acos(z_lo + (z_hi - z_lo) * c2), -M_PI + 2 * M_PI * c1);
      ASSERT_LT((d - e).cwiseAbs().maxCoeff(), kUnitTol) << "draw " << k;
    }
    ASSERT_NEAR(d.norm(), 1.0, kUnitTol);
    ASSERT_GE(d.z(), z_lo - kUnitTol);
    ASSERT_LE(d.z(), z_hi + kUnitTol);
    sz += d.z();
    sx += d.x();
    sy += d.y();
  }
  const double se_z = (z_hi - z_lo) / std::sqrt(12.0 * kDraws);
  EXPECT_NEAR(sz / kDraws, 0.5 * (z_lo + z_hi), kSigmas * se_z);
  // x = sin(theta) cos(phi) has variance E[sin^2 theta] / 2 <= 1/2.
  const double se_xy = std::sqrt(0.5 / kDraws);
  EXPECT_NEAR(sx / kDraws, 0.0, kSigmas * se_xy);
  EXPECT_NEAR(sy / kDraws, 0.0, kSigmas * se_xy);
}
