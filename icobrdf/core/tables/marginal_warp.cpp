#include "icobrdf/core/tables/marginal_warp.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "icobrdf/core/tables/bilinear_slices.hpp"
#include "icobrdf/core/support/error.hpp"

namespace icobrdf {

MarginalWarp2D::MarginalWarp2D(const std::vector<double>& density, int w, int h, ParameterGrid grid)
    : w_(w), h_(h), grid_(std::move(grid)) {
  if (w < 2 || h < 2)
    throw ArgumentError("density table: expected at least 2 x 2 nodes, found " + std::to_string(h) + " x " + std::to_string(w));
  const std::int64_t n = static_cast<std::int64_t>(w) * h, slices = grid_.slices();
  if (static_cast<std::int64_t>(density.size()) != slices * n)
    throw ArgumentError("density table: expected " + std::to_string(slices * n) + " values, found " + std::to_string(density.size()));
  data_.resize(static_cast<size_t>(slices * n));
  cond_.resize(static_cast<size_t>(slices * h * (w - 1)));
  marg_.resize(static_cast<size_t>(slices * (h - 1)));
  const double sx = 0.5 / (w - 1), sy = 0.5 / (h - 1);
  std::vector<double> row_total(static_cast<size_t>(h));
  for (std::int64_t s = 0; s < slices; ++s) {
    const double* d = density.data() + s * n;
    for (std::int64_t k = 0; k < n; ++k)
      if (!(std::isfinite(d[k]) && d[k] >= 0))
        throw ArgumentError("density table: slice " + std::to_string(s) + " value " + std::to_string(k) +
                            ": expected a finite number >= 0, found " + std::to_string(d[k]));
    double* cond = cond_.data() + s * h * (w - 1);
    for (int j = 0; j < h; ++j) {
      double acc = 0;
      for (int k = 0; k < w - 1; ++k) {
        acc += sx * (d[j * w + k] + d[j * w + k + 1]);
        cond[j * (w - 1) + k] = acc;
      }
      row_total[static_cast<size_t>(j)] = acc;
    }
    double* marg = marg_.data() + s * (h - 1);
    double acc = 0;
    for (int j = 0; j < h - 1; ++j) {
      acc += sy * (row_total[static_cast<size_t>(j)] + row_total[static_cast<size_t>(j + 1)]);
      marg[j] = acc;
    }
    if (!(acc > 0)) throw ArgumentError("density table: slice " + std::to_string(s) + " integrates to 0 (expected a positive density somewhere)");
    const double norm = 1.0 / acc;
    for (int k = 0; k < h * (w - 1); ++k) cond[k] *= norm;
    for (int j = 0; j < h - 1; ++j) marg[j] *= norm;
    for (std::int64_t k = 0; k < n; ++k) data_[static_cast<size_t>(s * n + k)] = d[k] * norm;
  }
}

double MarginalWarp2D::blended(const std::vector<double>& table, std::int64_t per_slice, std::int64_t at, const SliceBlend& b) const {
  double v = 0;
  for (int c = 0; c < b.count; ++c) v += b.weight[static_cast<size_t>(c)] * table[static_cast<size_t>(b.slice[static_cast<size_t>(c)] * per_slice + at)];
  return v;
}

double MarginalWarp2D::density(double x, double y, const SliceBlend& b) const {
  const PatchCoordinate px = patch_coordinate(x, w_), py = patch_coordinate(y, h_);
  const std::int64_t n = static_cast<std::int64_t>(w_) * h_, at = static_cast<std::int64_t>(py.index) * w_ + px.index;
  const double v00 = blended(data_, n, at, b), v10 = blended(data_, n, at + 1, b), v01 = blended(data_, n, at + w_, b),
               v11 = blended(data_, n, at + w_ + 1, b);
  return interpolate(interpolate(v00, v01, py.fraction), interpolate(v10, v11, py.fraction), px.fraction);
}

Eigen::Vector2d MarginalWarp2D::invert(double x, double y, const SliceBlend& b) const {
  const PatchCoordinate px = patch_coordinate(x, w_), py = patch_coordinate(y, h_);
  const std::int64_t n = static_cast<std::int64_t>(w_) * h_, at = static_cast<std::int64_t>(py.index) * w_ + px.index;
  const double fx = px.fraction, fy = py.fraction;
  const double v00 = blended(data_, n, at, b), v10 = blended(data_, n, at + 1, b), v01 = blended(data_, n, at + w_, b),
               v11 = blended(data_, n, at + w_ + 1, b);
  const double c0 = interpolate(v00, v01, fy), c1 = interpolate(v10, v11, fy);
  // x: partial patch integral (of the linear c0 .. c1 from 0 to fx: fx times its value at fx / 2), then the
  // rows' cumulative integrals before the patch, over the row total. Convex combinations throughout, so
  // that a positive density never cancels to 0 or below (see interpolate).
  double sx = fx * interpolate(c0, c1, 0.5 * fx) / (w_ - 1);
  const std::int64_t nc = static_cast<std::int64_t>(h_) * (w_ - 1), row = static_cast<std::int64_t>(py.index) * (w_ - 1);
  if (px.index > 0) {
    const double a = blended(cond_, nc, row + px.index - 1, b), c = blended(cond_, nc, row + (w_ - 1) + px.index - 1, b);
    sx += interpolate(a, c, fy);
  }
  const double r0 = blended(cond_, nc, row + w_ - 2, b), r1 = blended(cond_, nc, row + 2 * (w_ - 1) - 1, b);
  const double total = interpolate(r0, r1, fy);
  sx = total > 0 ? std::min(sx / total, 1.0) : 0.0;
  double sy = fy * interpolate(r0, r1, 0.5 * fy) / (h_ - 1);
  if (py.index > 0) sy += blended(marg_, h_ - 1, py.index - 1, b);
  return {sx, sy};
}

}  // namespace icobrdf
