#include "icobrdf/plot/colormap.hpp"

#include <algorithm>
#include <cmath>

namespace icobrdf::plot {
namespace {

struct Anchor {
  double t;
  Rgb c;
};

// Piecewise-linear in sRGB between anchors; roughly monotone in lightness on each side of zero.
constexpr Anchor kDiverging[] = {
    {-1.0, {0.05, 0.13, 0.42}}, {-0.5, {0.24, 0.36, 0.66}}, {0.0, {0.5, 0.5, 0.5}},
    {0.5, {0.80, 0.55, 0.30}},  {1.0, {1.0, 0.95, 0.72}},
};

// viridis at t = 0, 1/4, 1/2, 3/4, 1 (#440154, #3b528b, #21918c, #5ec962, #fde725).
constexpr Anchor kSequential[] = {
    {0.0, {0.267, 0.004, 0.329}}, {0.25, {0.231, 0.322, 0.545}}, {0.5, {0.129, 0.569, 0.549}},
    {0.75, {0.369, 0.788, 0.384}}, {1.0, {0.992, 0.906, 0.145}},
};

Rgb interpolate(const Anchor* anchors, int count, double t) {
  for (int k = 0; k + 1 < count; ++k) {
    const auto& a = anchors[k];
    const auto& b = anchors[k + 1];
    if (t <= b.t) {
      const double u = (t - a.t) / (b.t - a.t);
      return {a.c[0] + u * (b.c[0] - a.c[0]), a.c[1] + u * (b.c[1] - a.c[1]), a.c[2] + u * (b.c[2] - a.c[2])};
    }
  }
  return anchors[count - 1].c;
}

}  // namespace

Rgb sequential(double t) {
  if (!std::isfinite(t)) t = 0.0;
  return interpolate(kSequential, 5, std::clamp(t, 0.0, 1.0));
}

Rgb diverging(double t) {
  if (!std::isfinite(t)) t = 0.0;
  return interpolate(kDiverging, 5, std::clamp(t, -1.0, 1.0));
}

Rgb grey(double t) {
  if (!std::isfinite(t)) t = 0.0;
  const double v = 0.5 + 0.5 * std::clamp(t, -1.0, 1.0);
  return {v, v, v};
}

double srgb_encode(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
}

double srgb_decode(double v) {
  v = std::clamp(v, 0.0, 1.0);
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

}  // namespace icobrdf::plot
