#pragma once
// MarginalWarp2D: the continuous marginal-conditional warp of a bilinearly interpolated density on the unit
// square, with densities that depend on parameters (icobrdf/core/tables/parameter_grid.hpp). The RGL measured-BRDF format
// (Dupuy & Jakob 2018; icobrdf/io/rgl_bsdf.hpp) stores its visible-normal distribution this way, and its value
// tables live in the warp's input square.
//
// Per slice, the density is the bilinear interpolant p(x, y) of an h x w table (w columns along x, h rows
// along y, row-major, slices first as in icobrdf/core/tables/bilinear_slices.hpp), normalized so that its integral over the
// square is 1. The map sample -> point is: y from the marginal of p (integral over x), then x from the
// conditional of p given y, both in closed form for a piecewise linear density. invert(point) is its
// inverse: sample = (P(x | y), P_marginal(y)), with
//   - the conditional CDF along x at height y the linear blend, between rows j and j+1, of the rows' own
//     cumulative trapezoid integrals, plus the partial patch integral fx * lerp(c0, c1, fx / 2) / (w - 1)
//     (c0, c1 the density along the patch's left and right edges at y), divided by the blended row total;
//   - the marginal CDF at y the cumulative integral of the row totals up to row j, plus
//     fy * lerp(r0, r1, fy / 2) / (h - 1) (r0, r1 the totals of rows j and j+1).
// Across parameters every table (normalized density, row CDFs, marginal CDF) is blended with the same
// weights, so an in-between parameter gives the blend of the slices' tables, not a re-normalized blend.
// A constant density gives the identity map; a density a + b x gives x -> (a x + b x^2 / 2) / (a + b / 2).
// Inputs are clamped to [0, 1]. Precision: double throughout.
#include <Eigen/Core>

#include <cstdint>
#include <vector>

#include "icobrdf/core/tables/parameter_grid.hpp"

namespace icobrdf {

class MarginalWarp2D {
 public:
  MarginalWarp2D() = default;
  // ArgumentError for w or h < 2, a size other than slices * w * h, a negative or non-finite value, or a
  // slice whose interpolant integrates to 0 (the message names the slice).
  MarginalWarp2D(const std::vector<double>& density, int w, int h, ParameterGrid grid);
  const ParameterGrid& grid() const { return grid_; }
  int width() const { return w_; }
  int height() const { return h_; }
  // Point on the square -> sample on the square (the inverse of the warp).
  Eigen::Vector2d invert(double x, double y, const SliceBlend& blend) const;
  // The normalized density at a point (bilinear, blended).
  double density(double x, double y, const SliceBlend& blend) const;

 private:
  double blended(const std::vector<double>& table, std::int64_t per_slice, std::int64_t at, const SliceBlend& b) const;
  std::vector<double> data_, cond_, marg_;
  int w_ = 0, h_ = 0;
  ParameterGrid grid_;
};

}  // namespace icobrdf
