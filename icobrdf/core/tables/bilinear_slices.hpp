#pragma once
// BilinearSlices: a stack of 2-D tables on the unit square, interpolated bilinearly inside a table and
// multilinearly across tables (icobrdf/core/tables/parameter_grid.hpp). The value tables of the RGL measured-BRDF format
// (spectra, NDF, projected area; icobrdf/io/rgl_bsdf.hpp) are of this kind.
//
// Shapes: `values` holds grid.slices() tables of h rows x w columns (w, h >= 2), row-major, slice-major:
// value(slice s, row j, column k) = values[(s * h + j) * w + k], node (x, y) = (k / (w - 1), j / (h - 1)).
// eval(x, y): x and y are clamped to [0, 1]; the patch is (floor(x (w - 1)), floor(y (h - 1))) clamped
// to the last patch, and the value is lerp(lerp(v00, v10, fx), lerp(v01, v11, fx), fy) with the corner
// values blended across slices first. At a node the stored value comes back exactly (up to the blend).
#include <cstdint>
#include <vector>

#include "icobrdf/core/tables/parameter_grid.hpp"

namespace icobrdf {

class BilinearSlices {
 public:
  BilinearSlices() = default;
  // ArgumentError for w or h < 2 or values.size() != slices * w * h.
  BilinearSlices(std::vector<double> values, int w, int h, ParameterGrid grid);
  int width() const { return w_; }
  int height() const { return h_; }
  const ParameterGrid& grid() const { return grid_; }
  double eval(double x, double y, const SliceBlend& blend) const;
  double eval(double x, double y, const double* params) const { return eval(x, y, grid_.blend(params)); }

 private:
  std::vector<double> v_;
  int w_ = 0, h_ = 0;
  ParameterGrid grid_;
};

// Patch of a coordinate in [0, 1] on n >= 2 nodes: index in [0, n - 2] and the fraction in it.
struct PatchCoordinate {
  int index;
  double fraction;
};
PatchCoordinate patch_coordinate(double u, int n);

// Linear interpolation between a (t = 0) and b (t = 1) for t in [0, 1], written as the convex combination
// (1 - t) a + t b: exact at both ends, within [min(a, b), max(a, b)], and positive when a and b are. The
// form a + (b - a) t is not: with a = 4e31, b = 0.5 and t = 1 it cancels to 0 (a positive table then
// interpolated to 0 and a division by it gave inf; found by fuzz_rgl_bsdf).
inline double interpolate(double a, double b, double t) { return (1.0 - t) * a + t * b; }

}  // namespace icobrdf
