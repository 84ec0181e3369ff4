#pragma once
// Gauss-Legendre quadrature on [a, b]: n nodes, exact for polynomials of degree <= 2n - 1.
// Nodes by Newton's method on the three-term Legendre recurrence (started from Tricomi's asymptotic
// guess), weights 2 / ((1 - x^2) P_n'(x)^2); nodes and weights are accurate to a few ulps for n <= 1000.
#include <Eigen/Core>

namespace icobrdf {

struct QuadratureRule {
  Eigen::VectorXd nodes;    // ascending
  Eigen::VectorXd weights;  // sum = b - a
};

QuadratureRule gauss_legendre(int n, double a = -1.0, double b = 1.0);

}  // namespace icobrdf
