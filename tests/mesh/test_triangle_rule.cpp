// Stroud conical product rules: exactness on all monomials up to the stated degree, sharpness of the
// degree, interior points and positive weights; Gauss-Jacobi against closed-form nodes.
#include <gtest/gtest.h>

#include <cmath>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/mesh/triangle_rule.hpp"
#include "tests/support/unity_id.hpp"

using namespace icobrdf;

namespace ICOBRDF_UNITY_ID {
// Monomial integrals are O(1e-2..1e-20); a relative 1e-13 allows the rounding of up to 31^2 terms.
constexpr double kRelTol = 1e-13;

// Exact integral of xi^a eta^b over the reference triangle: a! b! / (a + b + 2)! (Dirichlet integral).
double exact_monomial(int a, int b) {
  return std::exp(std::lgamma(a + 1.0) + std::lgamma(b + 1.0) - std::lgamma(a + b + 3.0));
}

double rule_monomial(const TriangleRule& r, int a, int b) {
  double s = 0;
  for (int k = 0; k < r.size(); ++k) s += r.weight[k] * std::pow(r.xi[k], a) * std::pow(r.eta[k], b);
  return 0.5 * s;  // area of the reference triangle
}

TEST(TriangleRule, ExactUpToStatedDegree) {
  for (int d = 1; d <= 25; ++d) {
    const TriangleRule r = stroud_conical_rule(d);
    EXPECT_GE(r.degree, d);
    const int m = (d + 2) / 2;
    EXPECT_EQ(r.size(), m * m);
    for (int a = 0; a <= r.degree; ++a)
      for (int b = 0; a + b <= r.degree; ++b)
        EXPECT_NEAR(rule_monomial(r, a, b), exact_monomial(a, b), kRelTol * exact_monomial(a, b)) << d << " " << a << " " << b;
  }
}

TEST(TriangleRule, DegreeIsSharp) {
  // xi^(2m) needs the m-point Gauss-Jacobi rule beyond its degree 2m - 1: the error is of the order of
  // the rule's remainder, far above rounding.
  for (int d : {3, 7, 9, 13}) {
    const TriangleRule r = stroud_conical_rule(d);
    const int k = r.degree + 1;
    EXPECT_GT(std::abs(rule_monomial(r, k, 0) - exact_monomial(k, 0)), 1e3 * kRelTol * exact_monomial(k, 0)) << d;
  }
}

TEST(TriangleRule, PointsInsideWeightsPositive) {
  const TriangleRule r = stroud_conical_rule(9);
  for (int k = 0; k < r.size(); ++k) {
    EXPECT_GT(r.xi[k], 0.0);
    EXPECT_GT(r.eta[k], 0.0);
    EXPECT_LT(r.xi[k] + r.eta[k], 1.0);
    EXPECT_GT(r.weight[k], 0.0);
  }
  EXPECT_NEAR(r.weight.sum(), 1.0, 1e-15);
}

TEST(TriangleRule, GaussLegendreAndJacobiClosedForms) {
  Eigen::VectorXd x, w;
  gauss_jacobi(2, 0.0, 0.0, x, w);  // Legendre: +-1/sqrt(3), weights 1
  EXPECT_NEAR(x[0], -1.0 / std::sqrt(3.0), 1e-15);
  EXPECT_NEAR(x[1], 1.0 / std::sqrt(3.0), 1e-15);
  EXPECT_NEAR(w[0], 1.0, 1e-15);
  gauss_jacobi(3, 0.0, 0.0, x, w);  // 0, +-sqrt(3/5); 8/9, 5/9
  EXPECT_NEAR(x[1], 0.0, 1e-15);
  EXPECT_NEAR(x[2], std::sqrt(0.6), 1e-15);
  EXPECT_NEAR(w[1], 8.0 / 9.0, 1e-15);
  // Jacobi (1,0), one point: the mean of t under the weight (1 - t): -1/3, weight 2.
  gauss_jacobi(1, 1.0, 0.0, x, w);
  EXPECT_NEAR(x[0], -1.0 / 3.0, 1e-15);
  EXPECT_NEAR(w[0], 2.0, 1e-15);
}

TEST(TriangleRule, RejectsBadDegree) {
  EXPECT_THROW(stroud_conical_rule(0), ArgumentError);
  EXPECT_THROW(stroud_conical_rule(62), ArgumentError);
}

}  // namespace ICOBRDF_UNITY_ID
