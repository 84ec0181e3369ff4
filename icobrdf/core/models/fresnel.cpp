#include "icobrdf/core/models/fresnel.hpp"

#include <cmath>

namespace icobrdf {

double fresnel_schlick(double c, double f0) {
  const double m = 1.0 - c;
  const double m2 = m * m;
  return f0 + (1.0 - f0) * m2 * m2 * m;
}

double fresnel_dielectric(double c, double eta) {
  const double g2 = eta * eta - 1.0 + c * c;
  if (g2 < 0.0) return 1.0;
  const double g = std::sqrt(g2);
  if (g + c == 0.0) return 0.0;  // eta = 1 at c = 0: no interface
  const double a = (g - c) / (g + c);
  const double b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
  return 0.5 * a * a * (1.0 + b * b);
}

}  // namespace icobrdf
