#pragma once
// The colour scale of a picture's values: sequential for non-negative data, diverging (mid-grey = 0) only
// for signed data, linear or logarithmic, with the colour bar that reads it.
//
//   linear, non-negative:  u = v / top in [0, 1], sequential map (dark = 0, light = top)
//   linear, signed:        u = v / top in [-1, 1], diverging map
//   log, non-negative:     u = (log10 v - log10 bottom) / (log10 top - log10 bottom), bottom = top 10^-decades;
//                          values <= bottom (zero, and negative ringing) get the darkest colour
//   log, signed:           symmetric log, u = sign(v) log10(1 + |v|/bottom) / log10(1 + top/bottom): linear
//                          within +-bottom, logarithmic beyond (the spectrum's coefficients, differences)
// Data count as signed when their minimum is below -kSignedShare x top: rounding noise of a positive BRDF
// does not turn its picture diverging.
#include <Eigen/Core>

#include <string>
#include <vector>

#include "icobrdf/plot/colormap.hpp"
#include "icobrdf/plot/figure.hpp"

namespace icobrdf::plot {

// Below -1e-3 of the largest value a negative value is ringing or noise worth seeing, not rounding.
inline constexpr double kSignedShare = 1e-3;
// Decades a log scale spans by default: a glossy peak and its diffuse floor within one picture.
inline constexpr double kDefaultDecades = 4.0;

struct ValueScale {
  bool is_signed = false, log = false;
  double top = 1.0;     // largest |value| (> 0)
  double bottom = 0.0;  // log scales: the smallest value shown apart from zero
  // Position of v on the scale: [0, 1] for non-negative scales, [-1, 1] for signed ones (clamped).
  double unit(double v) const;
  // The value at a position (inverse of unit within the range).
  double value_at(double u) const;
  Rgb colour(double v) const;
  // Values worth a tick on the colour bar or an axis (within the range, ends included).
  std::vector<double> ticks() const;
};

// The scale of values (NaN entries ignored; all zero or none finite: top 1). `force_signed` for quantities
// that are signed by nature (differences, coefficients).
ValueScale value_scale(const std::vector<const Eigen::MatrixXd*>& values, bool log, double decades = kDefaultDecades,
                       bool force_signed = false);

// values (NaN = no data, transparent) through the scale.
Raster colorize(const Eigen::MatrixXd& values, const ValueScale& scale);

// A vertical colour bar at (x, y, w, h) with its ticks labelled and `label` (the unit) written vertically at
// its right. `channels` 3: three strips (red, green, blue), each the sRGB display ramp of its channel over a
// linear non-negative scale (the radiance of RGB sphere pictures).
void draw_scale_bar(Figure& fig, int x, int y, int w, int h, const ValueScale& scale, const std::string& label, int channels = 1);

}  // namespace icobrdf::plot
