#pragma once
// Test-only product quadrature on the upper hemisphere, independent of the library: Gauss-Legendre in
// t = rho^2 = 1 - cos(theta) on [0, 1] times the uniform rule in phi. Since dOmega = dt dphi, it integrates
//   p(t) * trig(phi)
// exactly for polynomial degree <= 2 G - 1 in t and trigonometric degree < P in phi. Products K_a K_b of
// hemisphere basis functions of order <= N are R_n^l R_m^l (a polynomial of degree (n + m)/2 <= N in t)
// times trig of degree <= 2N when l_a = +-l_b, and integrate to zero over phi otherwise, so G >= (N + 1)/2
// and P >= 2N + 1 make the rule exact for the Gram matrix of K to order N.
#include <Eigen/Core>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf::test {

// Gauss-Legendre nodes and weights on [-1, 1] by Newton's method on Bonnet's recurrence.
inline void gauss_legendre(int g, std::vector<double>& x, std::vector<double>& w) {
  x.assign(static_cast<size_t>(g), 0.0);
  w.assign(static_cast<size_t>(g), 0.0);
  // P_g'(z) from P_g and P_{g-1}; returns P_g(z) through `p`.
  const auto derivative = [g](double z, double& p) {
    double p0 = 1.0, p1 = z;
    for (int k = 2; k <= g; ++k) {
      const double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
      p0 = p1;
      p1 = p2;
    }
    p = p1;
    return g * (z * p1 - p0) / (z * z - 1.0);
  };
  for (int i = 0; i < g; ++i) {
    double z = std::cos(M_PI * (i + 0.75) / (g + 0.5)), p = 0.0;
    for (int it = 0; it < 100; ++it) {
      const double d = derivative(z, p);
      const double dz = p / d;
      z -= dz;
      if (std::abs(dz) < 1e-16) break;
    }
    const double dp = derivative(z, p);  // at the converged node
    x[static_cast<size_t>(i)] = z;
    w[static_cast<size_t>(i)] = 2.0 / ((1.0 - z * z) * dp * dp);
  }
}

struct HemisphereRule {
  RowMatrix3d dirs;        // Q x 3 unit vectors
  Eigen::VectorXd weights;  // Q, summing to 2 pi
  std::vector<double> theta, phi;
};

// G Gauss nodes in t times P uniform azimuths (offset by half a step so no node sits on phi = 0).
inline HemisphereRule hemisphere_rule(int g, int p) {
  if (g < 1 || p < 1) throw std::invalid_argument("hemisphere_rule: need g, p >= 1");
  std::vector<double> x, w;
  gauss_legendre(g, x, w);
  HemisphereRule r;
  r.dirs.resize(g * p, 3);
  r.weights.resize(g * p);
  int q = 0;
  for (int i = 0; i < g; ++i) {
    const double t = 0.5 * (x[static_cast<size_t>(i)] + 1.0);  // t = 1 - cos(theta) in [0, 1]
    const double wt = 0.5 * w[static_cast<size_t>(i)];
    const double z = 1.0 - t, s = std::sqrt(t * (2.0 - t));  // sin(theta) without cancellation
    for (int k = 0; k < p; ++k, ++q) {
      const double phi = 2.0 * M_PI * (k + 0.5) / p;
      r.dirs.row(q) << s * std::cos(phi), s * std::sin(phi), z;
      r.weights[q] = wt * 2.0 * M_PI / p;
      r.theta.push_back(std::acos(z));
      r.phi.push_back(phi);
    }
  }
  return r;
}

// Smallest rule exact for the Gram matrix of K up to order n.
inline HemisphereRule hemisphere_rule_for_order(int n) { return hemisphere_rule(n / 2 + 2, 2 * n + 2); }

// The product rule on hemisphere x hemisphere: every pair (i, j) of nodes, weight w_i w_j. Exact for the
// Gram matrix of pair functions (Helmholtz and isotropic modes) wherever `rule` is exact for K (Fubini).
struct PairRule {
  RowMatrix3d wi, wr;  // Q^2 x 3
  Eigen::VectorXd w;   // Q^2
};
inline PairRule pair_rule(const HemisphereRule& rule) {
  const Eigen::Index q = rule.dirs.rows();
  PairRule r;
  r.wi.resize(q * q, 3);
  r.wr.resize(q * q, 3);
  r.w.resize(q * q);
  for (Eigen::Index i = 0; i < q; ++i)
    for (Eigen::Index j = 0; j < q; ++j) {
      r.wi.row(i * q + j) = rule.dirs.row(i);
      r.wr.row(i * q + j) = rule.dirs.row(j);
      r.w[i * q + j] = rule.weights[i] * rule.weights[j];
    }
  return r;
}

}  // namespace icobrdf::test
