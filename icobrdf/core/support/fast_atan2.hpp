#pragma once
// atan2 for the hot loops that turn direction pairs into grid coordinates (icobrdf/core/models/half_angle_factors.cpp,
// icobrdf/core/tables/half_vector_table.cpp), about three times as fast as the C library's: the ratio
// r = min(|x|,|y|) / max(|x|,|y|) in [0, 1] (the one division) falls next to the nearest c_k = k/64, and atan(r)
// is the Taylor polynomial of atan about c_k of degree 7 in t = r - c_k, |t| <= 1/128, evaluated by Estrin's
// scheme. Its coefficients follow from those of atan' = 1/(1 + x^2) about c, b_n, by the recurrence
//   (1 + c^2) b_0 = 1,  (1 + c^2) b_1 + 2 c b_0 = 0,  (1 + c^2) b_n + 2 c b_(n-1) + b_(n-2) = 0,
// as a_0 = atan(c), a_n = b_(n-1) / n (stable: both roots of its characteristic polynomial have modulus
// 1 / sqrt(1 + c^2)); they are computed once, in long double. The first term left out, a_8 t^8, is below
// (1/128)^8 / 8 < 2e-18 (|b_n| <= (1 + c^2)^(-(n+1)/2) <= 1). At c_0 = 0 the even coefficients vanish, so
// r = 0 gives 0 exactly.
// Accuracy: within 5e-16 of std::atan2 (absolute, radians; measured on 4 million normal (y, x) pairs and in
// tests/core/support/test_fast_atan2.cpp). Quadrants and signed zeros as std::atan2; (0, 0) and non-finite
// arguments go to std::atan2.
#include <array>
#include <cmath>

#include "icobrdf/core/support/select_without_branch.hpp"

namespace icobrdf {

struct alignas(64) AtanTaylorRow {
  double a[8];  // Taylor coefficients of atan about c_k = k / 64: a[0] = atan(c_k), ...
};

inline const std::array<AtanTaylorRow, 65>& atan_taylor_table() {
  static const std::array<AtanTaylorRow, 65> table = [] {
    std::array<AtanTaylorRow, 65> t{};
    for (int k = 0; k <= 64; ++k) {
      const long double c = k / 64.0L, q = 1.0L + c * c;
      long double b[7];
      b[0] = 1.0L / q;
      b[1] = -2.0L * c * b[0] / q;
      for (int n = 2; n < 7; ++n) b[n] = -(2.0L * c * b[n - 1] + b[n - 2]) / q;
      t[static_cast<size_t>(k)].a[0] = static_cast<double>(std::atan(c));
      for (int n = 1; n < 8; ++n) t[static_cast<size_t>(k)].a[n] = static_cast<double>(b[n - 1] / n);
    }
    return t;
  }();
  return table;
}

inline double fast_atan2(double y, double x) {
  const double ax = std::abs(x), ay = std::abs(y);
  const bool swap = ay > ax;
  const double num = std::min(ax, ay), den = std::max(ax, ay);
  if (!(den > 0.0) || !(den <= 1.79769313486231570815e308)) return std::atan2(y, x);  // (0, 0), infinite or NaN
  const double r = num / den;
  const int k = static_cast<int>(r * 64.0 + 0.5);
  const double* a = atan_taylor_table()[static_cast<size_t>(k)].a;
  const double t = r - k * (1.0 / 64), t2 = t * t, t4 = t2 * t2;
  const double p = (a[0] + a[1] * t) + (a[2] + a[3] * t) * t2 + ((a[4] + a[5] * t) + (a[6] + a[7] * t) * t2) * t4;
  const double v = select_without_branch(swap, M_PI_2 - p, p);
  return std::copysign(select_without_branch(std::signbit(x), M_PI - v, v), y);
}

}  // namespace icobrdf
