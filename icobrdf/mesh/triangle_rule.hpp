#pragma once
// Cubature rules on the reference triangle T = {(xi, eta): xi, eta >= 0, xi + eta <= 1}.
//
// stroud_conical_rule(degree): Stroud's conical product rule. With m = ceil((degree + 1) / 2),
//   xi = u, eta = (1 - u) v,  weight = wJ(u) wL(v),
// where (u, wJ) is the m-point Gauss-Jacobi rule on [0, 1] for the weight (1 - u) and (v, wL) the m-point
// Gauss-Legendre rule on [0, 1]. It integrates every polynomial of total degree <= 2m - 1 in (xi, eta)
// exactly (the collapsed integrand f(u, (1-u) v) has degree <= 2m - 1 in u and in v). m^2 points, all
// strictly inside T. Nodes from the Golub-Welsch eigenvalue problem of the Jacobi matrices, polished by
// Newton steps on the three-term recurrence. Weights are normalized to sum to 1 (fractions of the area).
#include <Eigen/Core>

namespace icobrdf {

struct TriangleRule {
  int degree = 0;          // exact for polynomials of total degree <= degree
  Eigen::VectorXd xi, eta;  // nodes in T
  Eigen::VectorXd weight;   // sum 1: integral over T of f = area(T) * sum_k weight_k f(xi_k, eta_k)
  int size() const { return static_cast<int>(weight.size()); }
};

// degree >= 1 (ArgumentError otherwise, and for degree > 61).
TriangleRule stroud_conical_rule(int degree);

// m-point Gauss-Jacobi rule on [-1, 1] for the weight (1 - t)^alpha (1 + t)^beta (alpha, beta > -1):
// nodes ascending, weights summing to the integral of the weight function.
void gauss_jacobi(int m, double alpha, double beta, Eigen::VectorXd& nodes, Eigen::VectorXd& weights);

}  // namespace icobrdf
