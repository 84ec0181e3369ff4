#include <gtest/gtest.h>

#include <cmath>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/grid/gauss_legendre.hpp"

// Sums of O(n) terms of size O(1): 1e-14 allows their rounding.
constexpr double kQuadTol = 1e-14;

// Exactness: integral_{-1}^{1} x^k dx = 2/(k+1) for even k, 0 for odd k, for k <= 2n - 1.
TEST(GaussLegendre, ExactForPolynomialsUpToDegree2nMinus1) {
  for (int n : {1, 2, 3, 7, 20, 65, 129}) {
    const auto r = icobrdf::gauss_legendre(n);
    for (int k = 0; k <= 2 * n - 1 && k <= 60; ++k) {
      const double expected = k % 2 ? 0.0 : 2.0 / (k + 1);
      const double got = (r.nodes.array().pow(k) * r.weights.array()).sum();
      EXPECT_NEAR(got, expected, kQuadTol) << "n=" << n << " k=" << k;
    }
  }
}

// Known closed form for n = 2: nodes +-1/sqrt(3), weights 1.
TEST(GaussLegendre, TwoPointRule) {
  const auto r = icobrdf::gauss_legendre(2);
  EXPECT_NEAR(r.nodes[0], -1.0 / std::sqrt(3.0), kQuadTol);
  EXPECT_NEAR(r.nodes[1], 1.0 / std::sqrt(3.0), kQuadTol);
  EXPECT_NEAR(r.weights[0], 1.0, kQuadTol);
}

// On [0, 1]: integral of t^k = 1/(k+1); degree 2n with n nodes is NOT exact (the rule's limit is real).
TEST(GaussLegendre, IntervalMapAndDegreeLimit) {
  const int n = 5;
  const auto r = icobrdf::gauss_legendre(n, 0.0, 1.0);
  EXPECT_NEAR(r.weights.sum(), 1.0, kQuadTol);
  EXPECT_NEAR((r.nodes.array().pow(2 * n - 1) * r.weights.array()).sum(), 1.0 / (2 * n), kQuadTol);
  EXPECT_GT(std::abs((r.nodes.array().pow(2 * n) * r.weights.array()).sum() - 1.0 / (2 * n + 1)), 1e-8);
  EXPECT_THROW(icobrdf::gauss_legendre(0), icobrdf::ArgumentError);
}
