#pragma once
// Colour maps of the pictures. Colours are sRGB triples in [0, 1].
//   diverging(t), t in [-1, 1]: dark blue (-1) -> mid-grey (0) -> light warm yellow (+1); mid-grey
//                 (0.5, 0.5, 0.5) is exactly zero, so negative lobes (ringing) read as blue.
//   sequential(t), t in [0, 1]: dark violet (0) -> blue -> teal -> green -> yellow (1), lightness rising
//                 monotonically (the anchors of matplotlib's viridis): for non-negative data.
//   grey(t),      t in [-1, 1]: black (-1) -> mid-grey (0) -> white (+1), the paper's Fig. 3 scale.
// Values outside [-1, 1] are clamped.
#include <array>

namespace icobrdf::plot {

using Rgb = std::array<double, 3>;

Rgb diverging(double t);
Rgb sequential(double t);
Rgb grey(double t);

// sRGB transfer function of a linear value in [0, 1] (clamped) and its inverse.
double srgb_encode(double linear);
double srgb_decode(double encoded);

}  // namespace icobrdf::plot
