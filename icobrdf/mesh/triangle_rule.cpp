#include "icobrdf/mesh/triangle_rule.hpp"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <string>

#include "icobrdf/core/support/error.hpp"

namespace icobrdf {
namespace {

// Largest supported degree: 31 points per direction keep the Golub-Welsch nodes well separated.
constexpr int kMaxDegree = 61;

// Monic-recurrence Jacobi polynomial P_m^(alpha,beta)(t) and its derivative, by the standard three-term
// recurrence (used for the Newton polish of the nodes).
void jacobi_value(int m, double al, double be, double t, double& p, double& dp) {
  double p0 = 1.0, p1 = 0.5 * (al - be + (al + be + 2.0) * t);
  if (m == 0) {
    p = 1.0;
    dp = 0.0;
    return;
  }
  for (int k = 2; k <= m; ++k) {
    const double c = 2.0 * k + al + be;
    const double a1 = 2.0 * k * (k + al + be) * (c - 2.0);
    const double a2 = (c - 1.0) * (al * al - be * be);
    const double a3 = (c - 2.0) * (c - 1.0) * c;
    const double a4 = 2.0 * (k + al - 1.0) * (k + be - 1.0) * c;
    const double p2 = ((a2 + a3 * t) * p1 - a4 * p0) / a1;
    p0 = p1;
    p1 = p2;
  }
  p = p1;
  // (2m + a + b)(1 - t^2) P'_m = m [ (a - b) - (2m + a + b) t ] P_m + 2 (m + a)(m + b) P_{m-1}
  const double c = 2.0 * m + al + be;
  dp = (m * ((al - be) - c * t) * p1 + 2.0 * (m + al) * (m + be) * p0) / (c * (1.0 - t * t));
}

}  // namespace

void gauss_jacobi(int m, double al, double be, Eigen::VectorXd& nodes, Eigen::VectorXd& weights) {
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(m, m);
  for (int k = 0; k < m; ++k) {
    const double c = 2.0 * k + al + be;
    j(k, k) = (k == 0) ? (be - al) / (al + be + 2.0) : (be * be - al * al) / (c * (c + 2.0));
    if (k + 1 < m) {
      const double k1 = k + 1.0, c1 = 2.0 * k1 + al + be;
      const double b2 = 4.0 * k1 * (k1 + al) * (k1 + be) * (k1 + al + be) / (c1 * c1 * (c1 + 1.0) * (c1 - 1.0));
      j(k, k + 1) = j(k + 1, k) = std::sqrt(b2);
    }
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(j);
  nodes = es.eigenvalues();
  const double mu0 = std::pow(2.0, al + be + 1.0) * std::tgamma(al + 1.0) * std::tgamma(be + 1.0) / std::tgamma(al + be + 2.0);
  weights.resize(m);
  for (int k = 0; k < m; ++k) {
    // Newton polish of the node on the recurrence; the weight from the eigenvector keeps its accuracy.
    double t = nodes[k];
    for (int it = 0; it < 3; ++it) {
      double p, dp;
      jacobi_value(m, al, be, t, p, dp);
      if (dp == 0.0) break;
      t -= p / dp;
    }
    nodes[k] = t;
    weights[k] = mu0 * es.eigenvectors()(0, k) * es.eigenvectors()(0, k);
  }
  weights *= mu0 / weights.sum();
}

TriangleRule stroud_conical_rule(int degree) {
  if (degree < 1 || degree > kMaxDegree)
    throw ArgumentError("cubature degree " + std::to_string(degree) + " out of range: expected 1 <= degree <= " +
                        std::to_string(kMaxDegree));
  const int m = (degree + 2) / 2;  // ceil((degree + 1) / 2)
  Eigen::VectorXd tj, wj, tl, wl;
  gauss_jacobi(m, 1.0, 0.0, tj, wj);  // weight (1 - t) on [-1, 1]
  gauss_jacobi(m, 0.0, 0.0, tl, wl);  // Legendre
  TriangleRule r;
  r.degree = 2 * m - 1;
  r.xi.resize(m * m);
  r.eta.resize(m * m);
  r.weight.resize(m * m);
  for (int a = 0; a < m; ++a)
    for (int b = 0; b < m; ++b) {
      const double u = 0.5 * (1.0 + tj[a]), v = 0.5 * (1.0 + tl[b]);
      const int k = a * m + b;
      r.xi[k] = u;
      r.eta[k] = (1.0 - u) * v;
      r.weight[k] = wj[a] * wl[b];
    }
  r.weight /= r.weight.sum();
  return r;
}

}  // namespace icobrdf
