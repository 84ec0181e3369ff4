// GridNoise (icobrdf/core/tables/grid_noise.hpp): the noise of smooth fields on a grid plus Gaussian noise of a
// known sigma, the bias of the same fields without noise, and the inflation by a lobe narrower than the grid.
// Expected values are derived: the noise's sigma as drawn; the bias bound from the exact second differences of
// the noise-free field; the inflation from the quantiles of the normal distribution with the outliers' share.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>
#include <vector>

#include "icobrdf/core/tables/grid_noise.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

// Relative standard error of the estimate from N second differences: the MAD's 1.17 / sqrt(N), raised to
// 1.67 / sqrt(N) by the correlation of the differences along a line (grid_noise.hpp).
constexpr double kMadStandardError = 1.67;
// The estimate is judged within this many standard errors (a 4-sigma band: the draws are seeded, so the test
// is deterministic, and any seed passes with probability ~0.99994).
constexpr double kStandardErrors = 4.0;
constexpr int kNodes = 128;  // nodes per axis of the smooth fields
constexpr double kHalfPi = M_PI / 2;

// theta_j = j (pi/2) / (n - 1) down the rows, phi_k = k 2 pi / n along the columns.
template <class F>
std::vector<double> field(int n, F&& f) {
  std::vector<double> v(static_cast<size_t>(n) * n);
  for (int j = 0; j < n; ++j)
    for (int k = 0; k < n; ++k) v[static_cast<size_t>(j) * n + k] = f(kHalfPi * j / (n - 1), 2 * M_PI * k / n);
  return v;
}

std::vector<double> with_noise(std::vector<double> v, double sigma, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, sigma);
  for (double& x : v) x += n(rng);
  return v;
}

// Second differences of a table along both axes, exactly as the estimator forms them, of the noise-free field.
struct DifferenceRange {
  double lo = INFINITY, hi = -INFINITY;
  std::int64_t count = 0;
};
DifferenceRange difference_range(const std::vector<double>& v, int n) {
  DifferenceRange r;
  const auto at = [&](int j, int k) { return v[static_cast<size_t>(j) * n + k]; };
  for (int j = 0; j < n; ++j)
    for (int k = 1; k + 1 < n; ++k) {
      const double a = at(j, k - 1) - 2 * at(j, k) + at(j, k + 1), b = at(k - 1, j) - 2 * at(k, j) + at(k + 1, j);
      r.lo = std::min({r.lo, a, b});
      r.hi = std::max({r.hi, a, b});
      r.count += 2;
    }
  return r;
}

// Lambert's f cos(theta) = (rho / pi) cos(theta): along theta its second difference is exactly
// -2 (1 - cos h) (rho / pi) cos(theta), along phi 0.
constexpr double kAlbedo = 0.8;
double lambert(double theta, double) { return kAlbedo / M_PI * std::cos(theta); }
// A wide GGX distribution (alpha 0.5): D = alpha^2 / (pi (alpha^2 cos^2 + sin^2)^2), peak 1 / (pi alpha^2).
constexpr double kAlpha = 0.5;
double wide_ggx(double theta, double) {
  const double c = std::cos(theta), s = std::sin(theta), q = kAlpha * kAlpha * c * c + s * s;
  return kAlpha * kAlpha / (M_PI * q * q);
}

// The estimate of noisy data within the standard error plus the largest shift the smooth part can give the MAD:
// the median of |x_k + delta_k - c| moves by at most the range of delta, against a MAD of 0.6745 sqrt(6) sigma.
void expect_noise_found(const std::vector<double>& clean, double sigma, std::uint64_t seed, const char* what) {
  const DifferenceRange r = difference_range(clean, kNodes);
  const std::vector<double> noisy = with_noise(clean, sigma, seed);
  GridNoise g;
  g.add_table(noisy.data(), kNodes, kNodes);
  ASSERT_EQ(g.differences(), r.count);
  const double smooth_shift = (r.hi - r.lo) / (std::sqrt(6.0) * sigma / kMadToSigma);
  const double tol = kStandardErrors * kMadStandardError / std::sqrt(static_cast<double>(r.count)) + smooth_shift;
  std::cout << what << ": sigma " << sigma << ", estimate " << g.sigma() << " (relative tolerance " << tol << ")\n";
  EXPECT_NEAR(g.sigma() / sigma, 1.0, tol);
}

// Without noise the estimate is at most kMadToSigma / sqrt(6) times the range of the field's own differences.
void expect_bias_bounded(const std::vector<double>& clean, double sigma, const char* what) {
  const DifferenceRange r = difference_range(clean, kNodes);
  const double bound = kMadToSigma / std::sqrt(6.0) * (r.hi - r.lo);
  const double est = table_noise_sigma(clean.data(), kNodes, kNodes);
  std::cout << what << " without noise: estimate " << est << ", bound " << bound << ", noise added elsewhere " << sigma << "\n";
  EXPECT_LE(est, bound);
  EXPECT_LT(bound, 0.1 * sigma);  // far below the noise: the smooth part barely moves the estimate
}

TEST(GridNoise, LambertWithNoiseOfKnownSigma) {
  const double sigma = 0.01 * kAlbedo / M_PI;  // 1 % of the peak
  expect_noise_found(field(kNodes, lambert), sigma, 11, "Lambert");
  expect_bias_bounded(field(kNodes, lambert), sigma, "Lambert");
}

TEST(GridNoise, WideGgxWithNoiseOfKnownSigma) {
  const double sigma = 0.05 / (M_PI * kAlpha * kAlpha);  // 5 % of the peak
  expect_noise_found(field(kNodes, wide_ggx), sigma, 12, "GGX alpha 0.5");
  expect_bias_bounded(field(kNodes, wide_ggx), sigma, "GGX alpha 0.5");
}

double normal_cdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

// x with cdf(x) = p (increasing cdf), by bisection on [lo, hi].
template <class F>
double solve_increasing(F&& cdf, double p, double lo, double hi) {
  for (int it = 0; it < 200; ++it) {
    const double mid = (lo + hi) / 2;
    (cdf(mid) < p ? lo : hi) = mid;
  }
  return (lo + hi) / 2;
}

// A lobe narrower than the grid: spikes of 1000 sigma at isolated nodes (4 apart, away from the border), each
// making 6 outlying differences (3 along each axis: -2A at the spike, +A beside it) of the N. With outliers a
// share p of them (2/3 positive, 1/3 negative) and the clean differences N(0, 6 sigma^2), the population
// estimate solves
//   median:  (1 - p) Phi(m / s) + p / 3 = 1/2,
//   MAD:     (1 - p) [Phi((m + q) / s) - Phi((m - q) / s)] = 1/2,   s = sqrt(6) sigma,
// and the estimate is kMadToSigma q / sqrt(6): the inflation grid_noise.hpp documents (there for m = 0).
TEST(GridNoise, NarrowLobeInflatesByTheOutliersShare) {
  constexpr int n = 64, spacing = 4, first = 2;
  constexpr double sigma = 1.0, amplitude = 1000.0;
  std::vector<double> v = with_noise(std::vector<double>(static_cast<size_t>(n) * n, 0.0), sigma, 13);
  int spikes = 0;
  for (int j = first; j + 1 < n - 1; j += spacing)
    for (int k = first; k + 1 < n - 1; k += spacing, ++spikes) v[static_cast<size_t>(j) * n + k] += amplitude;
  GridNoise g;
  g.add_table(v.data(), n, n);
  const double total = static_cast<double>(g.differences()), p = 6.0 * spikes / total;
  const double s = std::sqrt(6.0) * sigma;
  const double m = s * solve_increasing([&](double x) { return (1 - p) * normal_cdf(x) + p / 3; }, 0.5, -5, 5);
  const double q = solve_increasing([&](double x) { return (1 - p) * (normal_cdf((m + x) / s) - normal_cdf((m - x) / s)); }, 0.5, 0, 10 * s);
  const double expected = kMadToSigma * q / std::sqrt(6.0);
  const double tol = kStandardErrors * kMadStandardError / std::sqrt((1 - p) * total);
  std::cout << "narrow lobe over a share " << p << " of the differences: estimate " << g.sigma() << " for sigma " << sigma
            << " (expected inflation " << expected << ")\n";
  EXPECT_GT(expected, 1.2);  // a real inflation, several standard errors away from 1: the test can tell
  EXPECT_NEAR(g.sigma() / expected, 1.0, tol);
}

TEST(GridNoise, MissingValuesAndTooFewDifferences) {
  // A line with a NaN leaves out the 3 differences that touch it.
  std::vector<double> line(40, 1.0);
  line[10] = NAN;
  GridNoise g;
  g.add_line(line.data(), 40, 1);
  EXPECT_EQ(g.differences(), 38 - 3);
  EXPECT_EQ(g.sigma(), 0.0);  // a constant line: no noise
  g.clear();
  g.add_line(line.data(), 20, 1);  // 18 - 3 differences: too few
  EXPECT_TRUE(std::isnan(g.sigma()));
  g.add_table(line.data(), 0, 5);  // empty: nothing added
  EXPECT_EQ(g.differences(), 15);
}

}  // namespace ICOBRDF_UNITY_ID
}  // namespace icobrdf
