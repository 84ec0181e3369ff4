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
// changes there (one program, old and new alternating, 2-GHz Intel Xeon). The table row is found from the bits
// of 64 r + 1.5 * 2^52, without a conversion to an integer and back: with the pair code's other changes of
// the same commit, RenderMaterial::eval of that lobe went from 86 to 73 ns (benchmarks/RESULTS.md).
// fast_atan2_upper (y >= 0) and fast_atan2_first_quadrant (y, x >= 0) leave out the fix-ups their domains do
// not need; bitwise fast_atan2 there (tests/core/support/test_fast_atan2.cpp).
#include <cmath>
#include <cstdint>
#include <cstring>

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
// Hidden: position-independent code then addresses it directly, not through the global offset table.
[[gnu::visibility("hidden")]] inline constexpr AtanTaylorTable kAtanTaylorTable = make_atan_taylor_table();

namespace fast_atan2_detail {
// atan(r) for r = num / den in [0, 1] from the table row of the nearest c_k.
// k, the integer nearest 64 r (ties to even), is read off the low bits of 64 r + 1.5 * 2^52 (one rounding; the
// sum minus 1.5 * 2^52 is k exactly): no float-to-integer conversion and back on the chain (the table row and t
// are ready about 6 cycles sooner than with int(64 r + 0.5), which chose the upper node at ties).
__attribute__((always_inline)) inline double atan_of_ratio(double r) {
  constexpr double kShift = 6755399441055744.0;  // 1.5 * 2^52: its unit in the last place is 1
  const double shifted = r * 64.0 + kShift;
  std::uint64_t bits;
  std::memcpy(&bits, &shifted, sizeof bits);
  const double* a = kAtanTaylorTable.row[bits & 0x7f].a;  // k <= 64
  const double t = r - (shifted - kShift) * (1.0 / 64), t2 = t * t, t4 = t2 * t2;
  return (a[0] + a[1] * t) + (a[2] + a[3] * t) * t2 + ((a[4] + a[5] * t) + (a[6] + a[7] * t) * t2) * t4;
}

// v = atan2(ay, ax) in [0, pi/2] for ay, ax >= +0, true; false where std::atan2 must decide: (0, 0) and two
// infinities make the ratio NaN, and one NaN need not (min and max may drop it), hence the unordered test. One
// infinite argument gives r = 0 and the exact 0 or pi/2.
__attribute__((always_inline)) inline bool first_quadrant(double ay, double ax, double& v) {
  const double r = std::min(ax, ay) / std::max(ax, ay);
  if (__builtin_expect(!(r <= 1.0) || std::isunordered(ay, ax), 0)) return false;
  const double p = atan_of_ratio(r);
  // The octant fix-up by arithmetic that rounds as a branch would, without leaving the vector registers: v is
  // pi/2 - p when ay > ax (s = -1, o = pi/2 = 2 (pi/4) exactly) and p otherwise (s = 1, o = 0).
  const double s = std::copysign(1.0, ax - ay), o = (1.0 - s) * M_PI_4;
  v = o + s * p;
  return true;
}

// The quadrant of x's sign: pi - v when x has its sign bit set, v otherwise, as (pi - copysign(pi, x)) / 2 +
// copysign(v, x).
__attribute__((always_inline)) inline double by_sign_of_x(double v, double x) {
  return 0.5 * (M_PI - std::copysign(M_PI, x)) + std::copysign(v, x);
}
}  // namespace fast_atan2_detail

__attribute__((always_inline)) inline double fast_atan2(double y, double x) {
  double v;
  if (!fast_atan2_detail::first_quadrant(std::abs(y), std::abs(x), v)) return std::atan2(y, x);
  return std::copysign(fast_atan2_detail::by_sign_of_x(v, x), y);
}

// fast_atan2 for y >= 0 (the upper half plane, where the pair code's angles lie): the last sign fix-up left out.
// Bitwise fast_atan2(y, x) for y >= +0, whose result is then >= +0; y = -0 gives +0 where fast_atan2 gives -0.
__attribute__((always_inline)) inline double fast_atan2_upper(double y, double x) {
  double v;
  if (!fast_atan2_detail::first_quadrant(y, std::abs(x), v)) return std::atan2(y, x);
  return fast_atan2_detail::by_sign_of_x(v, x);
}

// fast_atan2 for y >= +0 and x >= +0 (the first quadrant: an angle between two lengths): bitwise fast_atan2(y, x),
// without the quadrant fix-ups.
__attribute__((always_inline)) inline double fast_atan2_first_quadrant(double y, double x) {
  double v;
  if (!fast_atan2_detail::first_quadrant(y, x, v)) return std::atan2(y, x);
  return v;
}

}  // namespace icobrdf
