#pragma once
// atan2 for the hot loops that turn direction pairs into grid coordinates (icobrdf/core/models/half_angle_factors.cpp,
// icobrdf/core/tables/half_vector_table.cpp), about three times as fast as the C library's: the ratio
// r = min(|x|,|y|) / max(|x|,|y|) in [0, 1] (the one division) falls next to the nearest c_k = k/64, and atan(r)
// is the Taylor polynomial of atan about c_k of degree 7 in t = r - c_k, |t| <= 1/128, evaluated by Estrin's
// scheme. Its coefficients follow from those of atan' = 1/(1 + x^2) about c, b_n, by the recurrence
//   (1 + c^2) b_0 = 1,  (1 + c^2) b_1 + 2 c b_0 = 0,  (1 + c^2) b_n + 2 c b_(n-1) + b_(n-2) = 0,
// as a_0 = atan(c), a_n = b_(n-1) / n (stable: both roots of its characteristic polynomial have modulus
// 1 / sqrt(1 + c^2)); they are computed by the compiler, in long double. The first term left out, a_8 t^8, is below
// (1/128)^8 / 8 < 2e-18 (|b_n| <= (1 + c^2)^(-(n+1)/2) <= 1). At c_0 = 0 the even coefficients vanish, so
// r = 0 gives 0 exactly.
// Accuracy: within 5e-16 of std::atan2 (absolute, radians; measured on 4 million normal (y, x) pairs and in
// tests/core/support/test_fast_atan2.cpp). Quadrants and signed zeros as std::atan2; (0, 0), two infinite
// arguments and NaN go to std::atan2; one infinite argument gives std::atan2's exact 0, pi/2 or pi.
// Cost: the octant fix-ups are sign operations and one multiply-add each, not selects through integer
// registers, and the table is a compile-time constant (no first-use guard), so the function inlines whole: the
// pair code of a rank-2 half-angle lobe (three calls) went from 116 to 78 ns per pair with this and the loop
// changes there (one program, old and new alternating, 2-GHz Intel Xeon).
#include <cmath>

namespace icobrdf {

struct alignas(64) AtanTaylorRow {
  double a[8];  // Taylor coefficients of atan about c_k = k / 64: a[0] = atan(c_k), ...
};

// atan(c) for c in [0, 1] in long double at compile time, by Euler's series
//   atan(c) = sum_n 2^(2n) (n!)^2 / (2n + 1)! c^(2n+1) / (1 + c^2)^(n+1)
// of positive terms, each the last times (2n / (2n + 1)) c^2 / (1 + c^2) <= 1/2: 80 terms leave less than
// 2^-80 of the sum, below long double's rounding.
constexpr long double atan_by_euler_series(long double c) {
  const long double z = c * c / (1.0L + c * c);
  long double term = c / (1.0L + c * c), sum = term;
  for (int n = 1; n < 80; ++n) sum += term *= z * (2.0L * n) / (2.0L * n + 1.0L);
  return sum;
}

struct AtanTaylorTable {
  AtanTaylorRow row[65];
};

constexpr AtanTaylorTable make_atan_taylor_table() {
  AtanTaylorTable t{};
  for (int k = 0; k <= 64; ++k) {
    const long double c = k / 64.0L, q = 1.0L + c * c;
    long double b[7] = {};
    b[0] = 1.0L / q;
    b[1] = -2.0L * c * b[0] / q;
    for (int n = 2; n < 7; ++n) b[n] = -(2.0L * c * b[n - 1] + b[n - 2]) / q;
    t.row[k].a[0] = static_cast<double>(atan_by_euler_series(c));
    for (int n = 1; n < 8; ++n) t.row[k].a[n] = static_cast<double>(b[n - 1] / n);
  }
  return t;
}

// Computed by the compiler: no initialization on first use, so no guard on the hot path and fast_atan2 inlines.
inline constexpr AtanTaylorTable kAtanTaylorTable = make_atan_taylor_table();

__attribute__((always_inline)) inline double fast_atan2(double y, double x) {
  const double ax = std::abs(x), ay = std::abs(y);
  const double num = std::min(ax, ay), den = std::max(ax, ay);
  const double r = num / den;
  // (0, 0) and two infinities make r NaN; one NaN need not (min and max may drop it), hence the unordered test;
  // one infinite argument gives r = 0 and the exact 0, pi/2 or pi below.
  if (!(r <= 1.0) || std::isunordered(y, x)) return std::atan2(y, x);
  const int k = static_cast<int>(r * 64.0 + 0.5);
  const double* a = kAtanTaylorTable.row[k].a;
  const double t = r - k * (1.0 / 64), t2 = t * t, t4 = t2 * t2;
  const double p = (a[0] + a[1] * t) + (a[2] + a[3] * t) * t2 + ((a[4] + a[5] * t) + (a[6] + a[7] * t) * t2) * t4;
  // The octant fix-ups by arithmetic that rounds as the branches would, without leaving the vector registers:
  // v = o + s p is pi/2 - p when |y| > |x| (s = -1, o = pi/2 = 2 (pi/4) exactly) and p otherwise (s = 1, o = 0);
  // then (pi - copysign(pi, x)) / 2 + copysign(v, x) is pi - v when x has its sign bit set and v otherwise.
  const double s = std::copysign(1.0, ax - ay), o = (1.0 - s) * M_PI_4;
  const double v = o + s * p;
  return std::copysign(0.5 * (M_PI - std::copysign(M_PI, x)) + std::copysign(v, x), y);
}

}  // namespace icobrdf
