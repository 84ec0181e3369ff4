#include "icobrdf/core/grid/gauss_legendre.hpp"

#include <cmath>
#include <string>
#include <utility>

#include "icobrdf/core/support/error.hpp"

namespace icobrdf {

namespace {

// P_n(x) and P_n'(x) by the three-term recurrence (P_n' from P_n and P_{n-1}; x != +-1).
std::pair<double, double> legendre_and_derivative(int n, double x) {
  double p0 = 1.0, p1 = x;  // P_0, P_1
  for (int k = 2; k <= n; ++k) {
    const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
    p0 = p1;
    p1 = p2;
  }
  return {p1, n == 1 ? 1.0 : n * (x * p1 - p0) / (x * x - 1.0)};
}

}  // namespace

QuadratureRule gauss_legendre(int n, double a, double b) {
  if (n < 1) throw ArgumentError("Gauss-Legendre: expected at least 1 node, got " + std::to_string(n));
  QuadratureRule r;
  r.nodes.resize(n);
  r.weights.resize(n);
  const int half = (n + 1) / 2;
  for (int i = 0; i < half; ++i) {
    // Tricomi's approximation of the i-th largest root, then Newton on P_n.
    double x = std::cos(M_PI * (i + 0.75) / (n + 0.5)) * (1.0 - (n - 1.0) / (8.0 * n * n * n));
    for (int it = 0; it < 100; ++it) {
      const auto [pn, dp] = legendre_and_derivative(n, x);
      const double dx = pn / dp;
      x -= dx;
      if (std::abs(dx) <= 1e-16 * std::abs(x) + 1e-300) break;
    }
    const double dp = legendre_and_derivative(n, x).second;  // at the converged node, for the weight
    const double w = 2.0 / ((1.0 - x * x) * dp * dp);
    r.nodes[n - 1 - i] = x;
    r.nodes[i] = -x;
    r.weights[i] = r.weights[n - 1 - i] = w;
  }
  if (n % 2 == 1) r.nodes[n / 2] = 0.0;
  // Affine map to [a, b].
  r.nodes = (0.5 * (b - a)) * (r.nodes.array() + 1.0) + a;
  r.weights *= 0.5 * (b - a);
  return r;
}

}  // namespace icobrdf
