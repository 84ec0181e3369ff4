#include "icobrdf/core/tables/grid_noise.hpp"

#include <algorithm>
#include <cmath>

namespace icobrdf {
namespace {

// The median of v (reordered); v not empty.
double median_of(std::vector<double>& v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  const double upper = *mid;
  if (v.size() % 2 == 1) return upper;
  return (*std::max_element(v.begin(), mid) + upper) / 2;
}

}  // namespace

void GridNoise::add_line(const double* v, std::int64_t n, std::int64_t stride) {
  for (std::int64_t k = 1; k + 1 < n; ++k) {
    const double a = v[(k - 1) * stride], b = v[k * stride], c = v[(k + 1) * stride];
    const double d = a - 2 * b + c;
    if (std::isfinite(d)) d_.push_back(d);
  }
}

void GridNoise::add_table(const double* v, int rows, int cols) {
  if (rows <= 0 || cols <= 0) return;
  for (int j = 0; j < rows; ++j) add_line(v + static_cast<std::int64_t>(j) * cols, cols, 1);
  for (int k = 0; k < cols; ++k) add_line(v + k, rows, cols);
}

double GridNoise::sigma() const {
  if (differences() < kMinNoiseDifferences) return std::numeric_limits<double>::quiet_NaN();
  std::vector<double> d = d_;
  const double centre = median_of(d);
  for (double& x : d) x = std::abs(x - centre);
  return kMadToSigma * median_of(d) / std::sqrt(6.0);
}

double table_noise_sigma(const double* v, int rows, int cols) {
  GridNoise g;
  g.add_table(v, rows, cols);
  return g.sigma();
}

}  // namespace icobrdf
