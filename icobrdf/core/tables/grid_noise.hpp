#pragma once
// GridNoise: the standard deviation of independent noise on values sampled on a regular grid, estimated from
// the grid's own second differences (the data-side noise figure of measured materials: RGL value tables,
// icobrdf/io/rgl_bsdf.hpp; MERL tables, icobrdf/io/merl.hpp).
//
// Along a grid axis the second difference d = v[k-1] - 2 v[k] + v[k+1] of values v = s + n (s smooth, n
// independent noise of one standard deviation sigma) is d = h^2 s'' + O(h^4) + (n[k-1] - 2 n[k] + n[k+1]):
// its noise part has variance (1 + 4 + 1) sigma^2 = 6 sigma^2, and the smooth part cancels to O(h^2). The
// differences of every line of every axis added are pooled and the estimate is robust:
//   sigma = kMadToSigma * median_k |d_k - median(d)| / sqrt(6),
// the median absolute deviation (MAD) of Gaussian noise being sigma / kMadToSigma. The median is not moved by
// a minority of large differences (a lobe's peak, an edge), and centring on median(d) removes a curvature the
// whole grid shares.
//
// Assumes: noise independent from node to node, of one size over the grid added (a grid where it varies gets
// roughly its median size), and a signal smooth at the grid's scale (|h^2 s''| well below sqrt(6) sigma).
// Limits (tests/core/tables/test_grid_noise.cpp measures them):
//   * without noise the estimate is the smooth part's own spread: at most kMadToSigma / sqrt(6) times the
//     range of h^2 s'' over the grid (0.605 (max - min) of the second differences);
//   * a lobe narrower than the grid (a peak over a node or two) turns the differences it touches into
//     outliers; when they are a fraction p of all differences the estimate is inflated by
//     g(p) = Phi^-1(1/2 + 1/(4 (1 - p))) / Phi^-1(3/4): 1.13 at p = 0.1, 1.32 at 0.2, 1.59 at 0.3, 2.05 at 0.4
//     (Phi the normal CDF); beyond p = 0.5 the estimate is the lobe's, not the noise's. A lobe spread over
//     many nodes (as the RGL files' vndf warp spreads their peaks) is smooth at the grid's scale instead;
//   * the statistical error of the MAD of N Gaussian differences is about 1.17 / sqrt(N) relative; the
//     differences of one line are correlated (-2/3 between neighbours, 1/6 two apart), which raises it to
//     about 1.67 / sqrt(N).
#include <cstdint>
#include <limits>
#include <vector>

namespace icobrdf {

inline constexpr double kMadToSigma = 1.482602218505602;  // 1 / Phi^-1(3/4)
// Fewer differences than this give no estimate (NaN): the MAD of so few has a relative error above 0.3.
inline constexpr std::int64_t kMinNoiseDifferences = 32;

class GridNoise {
 public:
  // Adds the second differences of n values v[0], v[stride], ..., v[(n - 1) stride]; a difference with a
  // non-finite value (a missing sample) is left out. Lines of fewer than 3 values add nothing.
  void add_line(const double* v, std::int64_t n, std::int64_t stride);
  // Both axes of a rows x cols table, row-major (value (j, k) at v[j * cols + k]).
  void add_table(const double* v, int rows, int cols);
  std::int64_t differences() const { return static_cast<std::int64_t>(d_.size()); }
  // The estimate above [units of the values]; NaN with fewer than kMinNoiseDifferences differences.
  double sigma() const;
  void clear() { d_.clear(); }

 private:
  std::vector<double> d_;
};

// The estimate of one table (GridNoise::add_table, then sigma()).
double table_noise_sigma(const double* v, int rows, int cols);

}  // namespace icobrdf
