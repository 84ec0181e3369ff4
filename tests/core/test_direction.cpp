#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/direction.hpp"

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
