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

}  // namespace

Rgb diverging(double t) {
  if (!std::isfinite(t)) t = 0.0;
  t = std::clamp(t, -1.0, 1.0);
  for (int k = 0; k + 1 < 5; ++k) {
    const auto& a = kDiverging[k];
    const auto& b = kDiverging[k + 1];
    if (t <= b.t) {
      const double u = (t - a.t) / (b.t - a.t);
      return {a.c[0] + u * (b.c[0] - a.c[0]), a.c[1] + u * (b.c[1] - a.c[1]), a.c[2] + u * (b.c[2] - a.c[2])};
    }
  }
  return kDiverging[4].c;
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
