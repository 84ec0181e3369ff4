#pragma once
// Chi-squared goodness of fit of sampled directions against a density on the hemisphere (the test
// pbrt-v4 applies to its BxDFs), shared by the sampling tests.
//
// Bins: nz x nphi equal cells of (cos theta, phi) in [0, 1] x [-pi, pi). Expected counts: n times the
// integral of the density over each bin, by an independent midpoint rule of sub x sub points per bin
// (dOmega = dcos dphi); the density is called once, on all those points (rows of a RowMatrix3d). Bins whose expected count is below
// kMinExpected are pooled into one bin (the chi-squared approximation needs about 5 per bin); draws where
// the density integrates to 0 make the statistic infinite. The statistic has (bins used - 1)
// degrees of freedom; the p-value is the regularized upper incomplete gamma function Q(dof / 2, chi2 / 2).
#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <vector>

#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf::test_support {

// Regularized upper incomplete gamma Q(a, x), a > 0, x >= 0: the power series of P for x < a + 1, else the
// continued fraction of Q evaluated by the modified Lentz method; both to about 1e-15 relative.
inline double gamma_q(double a, double x) {
  if (x <= 0) return 1.0;
  const double log_prefix = a * std::log(x) - x - std::lgamma(a);
  if (x < a + 1) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 100000 && std::abs(term) > std::abs(sum) * 1e-17; ++n) {
      term *= x / (a + n);
      sum += term;
    }
    return 1.0 - sum * std::exp(log_prefix);
  }
  const double tiny = 1e-300;
  double b = x + 1 - a, c = 1 / tiny, d = 1 / b, h = d;
  for (int i = 1; i < 100000; ++i) {
    const double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1) < 1e-16) break;
  }
  return std::exp(log_prefix) * h;
}

struct ChiSquareResult {
  double chi2 = 0;
  int dof = 0;
  double p_value = 0;
  double expected_total = 0;  // integral of the density over the hemisphere (by the same quadrature)
};

inline constexpr double kMinExpected = 5.0;

// rows x cols directions at the midpoints of equal cells in (cos theta, phi), phi from -pi, row-major: the
// midpoint rule on the upper hemisphere, each point standing for the solid angle 2 pi / (rows cols).
inline RowMatrix3d midpoint_directions(int rows, int cols) {
  const double dz = 1.0 / rows, dphi = 2 * M_PI / cols;
  RowMatrix3d points(static_cast<Eigen::Index>(rows) * cols, 3);
  for (int a = 0; a < rows; ++a)
    for (int b = 0; b < cols; ++b) {
      const double z = (a + 0.5) * dz, phi = -M_PI + (b + 0.5) * dphi, st = std::sqrt(std::max(0.0, 1 - z * z));
      points.row(static_cast<Eigen::Index>(a) * cols + b) << st * std::cos(phi), st * std::sin(phi), z;
    }
  return points;
}

inline ChiSquareResult chi_square_directions(const std::vector<Eigen::Vector3d>& samples,
                                             const std::function<Eigen::VectorXd(const RowMatrix3d&)>& density, int nz,
                                             int nphi, int sub) {
  const int bins = nz * nphi;
  std::vector<double> observed(bins, 0.0), expected(bins, 0.0);
  for (const auto& w : samples) {
    const double z = std::min(std::max(w.z(), 0.0), 1.0);
    const double phi = std::atan2(w.y(), w.x());
    const int iz = std::min(static_cast<int>(z * nz), nz - 1);
    const int ip = std::min(std::max(static_cast<int>((phi + M_PI) / (2 * M_PI) * nphi), 0), nphi - 1);
    observed[iz * nphi + ip] += 1;
  }
  const double dz = 1.0 / (nz * sub), dphi = 2 * M_PI / (nphi * sub);
  const int rows = nz * sub, cols = nphi * sub;
  const Eigen::VectorXd values = density(midpoint_directions(rows, cols));
  ChiSquareResult r;
  for (int a = 0; a < rows; ++a)
    for (int b = 0; b < cols; ++b) {
      const double m = values[static_cast<Eigen::Index>(a) * cols + b] * dz * dphi;
      expected[(a / sub) * nphi + b / sub] += m;
      r.expected_total += m;
    }
  const double n = static_cast<double>(samples.size());
  std::vector<int> order(bins);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return expected[a] < expected[b]; });
  double pool_e = 0, pool_o = 0;
  int used = 0;
  for (int k : order) {
    const double e = expected[k] * n, o = observed[k];
    if (e < kMinExpected) {
      pool_e += e;
      pool_o += o;
      continue;
    }
    r.chi2 += (o - e) * (o - e) / e;
    ++used;
  }
  if (pool_e > 0 || pool_o > 0) {  // observed draws where the density is 0 give an infinite statistic
    r.chi2 += pool_e > 0 ? (pool_o - pool_e) * (pool_o - pool_e) / pool_e : std::numeric_limits<double>::infinity();
    ++used;
  }
  r.dof = used - 1;
  r.p_value = r.dof > 0 ? gamma_q(r.dof / 2.0, r.chi2 / 2.0) : 0.0;
  return r;
}

}  // namespace icobrdf::test_support
