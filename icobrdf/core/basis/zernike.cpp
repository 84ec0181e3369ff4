#include "icobrdf/core/basis/zernike.hpp"

#include <string>
#include <vector>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/horizon.hpp"

namespace icobrdf {

namespace {

// Radii computed from unit vectors may exceed 1 by a few ulps at the horizon (rho = 1): up to
// 1 + kHorizonSlack they are clamped to 1 (icobrdf/core/basis/horizon.hpp).

inline int row_start(int n) { return (n + 1) * (n + 1) / 4; }

void check_zernike_order(int order, const char* where) {
  if (order < 0 || order > kMaxZernikeOrder)
    throw ArgumentError(std::string(where) + ": order must be in [0, " + std::to_string(kMaxZernikeOrder) +
                        "], got " + std::to_string(order));
}

void check_pair(int n, int l, const char* where) {
  if (n < 0 || l < 0 || l > n || (n - l) % 2 != 0)
    throw ArgumentError(std::string(where) + ": need 0 <= l <= n with n - l even, got n = " + std::to_string(n) +
                        ", l = " + std::to_string(l));
}

double checked_rho(double rho, const char* where) {
  if (!(rho >= 0.0 && rho <= 1.0 + kHorizonSlack))
    throw ArgumentError(std::string(where) + ": rho must be in [0, 1], got " + std::to_string(rho));
  return rho > 1.0 ? 1.0 : rho;
}

}  // namespace

int zernike_radial_count(int order) {
  check_zernike_order(order, "zernike_radial_count");
  return row_start(order + 1);
}

int zernike_radial_index(int n, int l) {
  check_pair(n, l, "zernike_radial_index");
  return row_start(n) + (l - n % 2) / 2;
}

void zernike_radial_all(int order, double rho, double* out) {
  check_zernike_order(order, "zernike_radial_all");
  rho = checked_rho(rho, "zernike_radial_all");
  out[0] = 1.0;  // R_0^0
  if (order == 0) return;
  out[1] = rho;  // R_1^1
  const double two_rho = 2.0 * rho;
  for (int n = 2; n <= order; ++n) {
    double* __restrict cur = out + row_start(n);
    const double* __restrict prev = out + row_start(n - 1);
    const double* __restrict prev2 = out + row_start(n - 2);
    const int last = n / 2;  // index of l = n in row n
    if (n % 2 == 0) {
      // Row n: l = 2i. Row n-1: l' = 2i' + 1, so l - 1 -> i' = i - 1 and l + 1 -> i' = i; at l = 0, |l-1| = 1.
      cur[0] = two_rho * prev[0] - prev2[0];
      for (int i = 1; i < last; ++i) cur[i] = rho * (prev[i - 1] + prev[i]) - prev2[i];
      cur[last] = rho * prev[last - 1];
    } else {
      // Row n: l = 2i + 1. Row n-1: l' = 2i', so l - 1 -> i' = i and l + 1 -> i' = i + 1.
      for (int i = 0; i < last; ++i) cur[i] = rho * (prev[i] + prev[i + 1]) - prev2[i];
      cur[last] = rho * prev[last];
    }
  }
}

double zernike_radial(int n, int l, double rho) {
  check_pair(n, l, "zernike_radial");
  check_zernike_order(n, "zernike_radial");
  std::vector<double> all(static_cast<size_t>(row_start(n + 1)));
  zernike_radial_all(n, rho, all.data());
  return all[static_cast<size_t>(row_start(n) + (l - n % 2) / 2)];
}

}  // namespace icobrdf
