#include "icobrdf/core/tables/bilinear_slices.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "icobrdf/core/support/error.hpp"

namespace icobrdf {

PatchCoordinate patch_coordinate(double u, int n) {
  const double p = (std::isnan(u) ? 0.0 : std::clamp(u, 0.0, 1.0)) * (n - 1);
  const int i = std::min(static_cast<int>(p), n - 2);
  return {i, p - i};
}

BilinearSlices::BilinearSlices(std::vector<double> values, int w, int h, ParameterGrid grid)
    : v_(std::move(values)), w_(w), h_(h), grid_(std::move(grid)) {
  if (w < 2 || h < 2)
    throw ArgumentError("bilinear table: expected at least 2 x 2 nodes, found " + std::to_string(h) + " x " + std::to_string(w));
  const std::int64_t expected = grid_.slices() * w * h;
  if (static_cast<std::int64_t>(v_.size()) != expected)
    throw ArgumentError("bilinear table: expected " + std::to_string(expected) + " values, found " + std::to_string(v_.size()));
}

double BilinearSlices::eval(double x, double y, const SliceBlend& b) const {
  const PatchCoordinate px = patch_coordinate(x, w_), py = patch_coordinate(y, h_);
  const std::int64_t n = static_cast<std::int64_t>(w_) * h_, at = static_cast<std::int64_t>(py.index) * w_ + px.index;
  double v00 = 0, v10 = 0, v01 = 0, v11 = 0;
  for (int c = 0; c < b.count; ++c) {
    const double wt = b.weight[static_cast<size_t>(c)];
    const double* s = v_.data() + b.slice[static_cast<size_t>(c)] * n + at;
    v00 += wt * s[0];
    v10 += wt * s[1];
    v01 += wt * s[w_];
    v11 += wt * s[w_ + 1];
  }
  return interpolate(interpolate(v00, v10, px.fraction), interpolate(v01, v11, px.fraction), py.fraction);
}

}  // namespace icobrdf
