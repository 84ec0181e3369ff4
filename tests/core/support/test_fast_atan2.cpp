// fast_atan2 against std::atan2: random arguments of every quadrant and magnitude, the octant boundaries
// (|y| = |x|), the table's centres r = k/64 and the ends of their intervals, axes, signed zeros, infinities and NaN.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "icobrdf/core/support/fast_atan2.hpp"
#include "tests/support/unity_id.hpp"

using namespace icobrdf;

namespace ICOBRDF_UNITY_ID {
// The Taylor polynomials are accurate to 2e-18; what remains is the rounding of a handful of operations on
// values up to pi: a few ulps of pi (4.4e-16 measured).
constexpr double kAtan2Tol = 1e-15;

TEST(FastAtan2, AgreesWithTheLibraryOnRandomArguments) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n;
  std::uniform_real_distribution<double> e(-30, 30);
  double worst = 0;
  for (int i = 0; i < 1000000; ++i) {
    const double y = n(rng) * std::pow(10.0, e(rng)), x = n(rng) * std::pow(10.0, e(rng));
    worst = std::max(worst, std::abs(fast_atan2(y, x) - std::atan2(y, x)));
  }
  EXPECT_LE(worst, kAtan2Tol);
}

TEST(FastAtan2, BoundariesAxesAndSignedZeros) {
  // The Taylor centres c_k = k/64 and the ends of their intervals (k + 1/2)/64, where the polynomial is used
  // farthest from its centre.
  for (int k = 0; k <= 64; ++k)
    for (double sy : {1.0, -1.0})
      for (double sx : {1.0, -1.0}) {
        const double r = k / 64.0;
        EXPECT_NEAR(fast_atan2(sy * std::min(r + 1.0 / 128, 1.0), sx), std::atan2(sy * std::min(r + 1.0 / 128, 1.0), sx), kAtan2Tol) << k;
        EXPECT_NEAR(fast_atan2(sy * std::nextafter(r + 1.0 / 128, 0.0), sx), std::atan2(sy * std::nextafter(r + 1.0 / 128, 0.0), sx), kAtan2Tol) << k;
        EXPECT_NEAR(fast_atan2(sy * r, sx * 1.0), std::atan2(sy * r, sx * 1.0), kAtan2Tol) << k;
        EXPECT_NEAR(fast_atan2(sy * 1.0, sx * r), std::atan2(sy * 1.0, sx * r), kAtan2Tol) << k;
        EXPECT_NEAR(fast_atan2(sy * (r + 1.0 / 16), sx), std::atan2(sy * (r + 1.0 / 16), sx), kAtan2Tol) << k;
      }
  for (double y : {0.0, -0.0})
    for (double x : {0.0, -0.0, 2.0, -2.0}) EXPECT_EQ(fast_atan2(y, x), std::atan2(y, x)) << y << " " << x;
  EXPECT_EQ(fast_atan2(3.0, 0.0), std::atan2(3.0, 0.0));
  EXPECT_EQ(fast_atan2(-3.0, -0.0), std::atan2(-3.0, -0.0));
}

TEST(FastAtan2, InfinitiesAndNaNAsTheLibrary) {
  // One infinite argument takes the polynomial path with r = 0 and must give std::atan2's exact values (0, pi/2,
  // pi with their signs) bit for bit; two infinities and NaN go to std::atan2 itself.
  const double inf = INFINITY;
  for (double y : {inf, -inf, 1.5, -1.5, 0.0, -0.0, 1e308, -1e-300})
    for (double x : {inf, -inf, 1.5, -1.5, 0.0, -0.0, 1e308, -1e-300}) {
      const double a = fast_atan2(y, x), b = std::atan2(y, x);
      EXPECT_TRUE(a == b && std::signbit(a) == std::signbit(b)) << y << " " << x << ": " << a << " against " << b;
    }
  EXPECT_TRUE(std::isnan(fast_atan2(NAN, 1.0)) && std::isnan(fast_atan2(1.0, NAN)) && std::isnan(fast_atan2(NAN, inf)));
}

TEST(FastAtan2, UpperAndFirstQuadrantFormsAreBitwiseTheGeneralOne) {
  // On their domains (y >= +0; y, x >= +0) the shorter forms leave out only fix-ups that change nothing: random
  // arguments of every magnitude, the ties between two Taylor centres (r = (k + 1/2)/64 exactly), the octant
  // boundary, zeros and infinities.
  const auto same = [](double a, double b) { return (a == b && std::signbit(a) == std::signbit(b)) || (std::isnan(a) && std::isnan(b)); };
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(0, 1), e(-30, 30);
  std::vector<std::pair<double, double>> args;
  for (int i = 0; i < 200000; ++i) args.emplace_back(u(rng) * std::pow(10.0, e(rng)), (u(rng) - 0.5) * std::pow(10.0, e(rng)));
  for (int k = 0; k < 64; ++k) args.emplace_back((k + 0.5) / 64, 1.0), args.emplace_back(1.0, (k + 0.5) / 64), args.emplace_back(1.0, -(k + 0.5) / 64);
  const double inf = INFINITY;
  for (double y : {0.0, 1.0, 2.5, inf})
    for (double x : {0.0, -0.0, 1.0, -1.0, 2.5, inf, -inf}) args.emplace_back(y, x);
  for (const auto& [y, x] : args) {
    ASSERT_TRUE(same(fast_atan2_upper(y, x), fast_atan2(y, x))) << y << " " << x;
    if (!std::signbit(x)) {
      ASSERT_TRUE(same(fast_atan2_first_quadrant(y, x), fast_atan2(y, x))) << y << " " << x;
    }
  }
}

}  // namespace ICOBRDF_UNITY_ID
