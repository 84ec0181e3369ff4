#pragma once
// select_without_branch(c, a, b): c ? a : b chosen on the bits, without a conditional jump, for hot loops whose
// conditions are data that a branch predictor would miss about half the time (the canonical sign of a pair's
// (d_x, d_y) in icobrdf/core/models/half_angle_factors.cpp). It moves both values through integer registers:
// where the choice can be written as arithmetic that rounds the same way (fast_atan2's octant fix-ups), that
// is shorter. Exact: returns a or b bit for bit (signed zeros and NaNs kept).
#include <cstdint>
#include <cstring>

namespace icobrdf {

inline double select_without_branch(bool c, double a, double b) {
  std::uint64_t ua, ub;
  std::memcpy(&ua, &a, sizeof ua);
  std::memcpy(&ub, &b, sizeof ub);
  const std::uint64_t m = 0 - static_cast<std::uint64_t>(c);
  const std::uint64_t u = (ua & m) | (ub & ~m);
  double v;
  std::memcpy(&v, &u, sizeof v);
  return v;
}

}  // namespace icobrdf
