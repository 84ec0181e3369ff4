#include "core/hemisphere_basis.hpp"

#include <array>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "core/lambert_map.hpp"
#include "core/zernike.hpp"

namespace icobrdf {

namespace {

constexpr int kMaxRadial = (kMaxZernikeOrder + 2) * (kMaxZernikeOrder + 2) / 4;

void check_order(int order, const char* where) {
  if (order < 0 || order > kMaxZernikeOrder)
    throw ArgumentError(std::string(where) + ": order must be in [0, " + std::to_string(kMaxZernikeOrder) +
                        "], got " + std::to_string(order));
}

}  // namespace

int hemisphere_basis_count(int order) {
  check_order(order, "hemisphere_basis_count");
  return (order + 1) * (order + 2) / 2;
}

int hemisphere_basis_order(int count) {
  for (int n = 0; n <= kMaxZernikeOrder; ++n)
    if ((n + 1) * (n + 2) / 2 == count) return n;
  throw ArgumentError("hemisphere_basis_order: " + std::to_string(count) +
                      " is not (N+1)(N+2)/2 for any order N in [0, " + std::to_string(kMaxZernikeOrder) + "]");
}

int ansi_index(int n, int l) {
  if (n < 0 || l < -n || l > n || (n - l) % 2 != 0)
    throw ArgumentError("ansi_index: need n >= 0, |l| <= n, n - l even, got n = " + std::to_string(n) +
                        ", l = " + std::to_string(l));
  return (n * (n + 2) + l) / 2;
}

BasisIndex ansi_to_nl(int j) {
  if (j < 0) throw ArgumentError("ansi_to_nl: index must be >= 0, got " + std::to_string(j));
  int n = static_cast<int>((std::sqrt(8.0 * j + 1.0) - 1.0) / 2.0);
  while (n * (n + 1) / 2 > j) --n;            // guard the floating-point estimate
  while ((n + 1) * (n + 2) / 2 <= j) ++n;
  return {n, 2 * (j - n * (n + 1) / 2) - n};
}

void hemisphere_basis_eval(int order, const Eigen::Vector3d& unit_dir, double* out) {
  check_order(order, "hemisphere_basis_eval");
  std::array<double, kMaxRadial> radial;
  std::array<double, kMaxZernikeOrder + 1> cos_l, sin_l;
  const double rho2 = lambert_rho_squared(unit_dir);
  zernike_radial_all(order, std::sqrt(rho2), radial.data());
  // Azimuth from (x, y) without trigonometry; cos(l phi) + i sin(l phi) = (cos phi + i sin phi)^l.
  const double s = std::sqrt(unit_dir.x() * unit_dir.x() + unit_dir.y() * unit_dir.y());
  const double c1 = s > 0.0 ? unit_dir.x() / s : 1.0;
  const double s1 = s > 0.0 ? unit_dir.y() / s : 0.0;
  cos_l[0] = 1.0;
  sin_l[0] = 0.0;
  for (int l = 1; l <= order; ++l) {
    cos_l[l] = cos_l[l - 1] * c1 - sin_l[l - 1] * s1;
    sin_l[l] = sin_l[l - 1] * c1 + cos_l[l - 1] * s1;
  }
  int j = 0;
  for (int n = 0; n <= order; ++n) {
    const double norm = std::sqrt((n + 1) / M_PI);
    const double* row = radial.data() + (n + 1) * (n + 1) / 4;  // R_n^{n mod 2}, R_n^{n mod 2 + 2}, ...
    for (int l = -n; l <= n; l += 2, ++j) {
      const int al = l < 0 ? -l : l;
      const double r = row[(al - n % 2) / 2];
      const double az = l > 0 ? cos_l[al] : (l < 0 ? sin_l[al] : M_SQRT1_2);
      out[j] = norm * r * az;
    }
  }
}

Eigen::MatrixXd hemisphere_basis_matrix(int order, const RowMatrix3d& dirs) {
  const int count = hemisphere_basis_count(order);
  const Eigen::Index rows = dirs.rows();
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> out(rows, count);
  // Per-row work is independent; exceptions (a direction below the horizon) are collected outside the loop.
  bool bad = false;
  Eigen::Index first_bad = -1;
#pragma omp parallel for schedule(static) if (rows * count > 200000)
  for (Eigen::Index r = 0; r < rows; ++r) {
    if (!(dirs(r, 2) >= -1e-12)) {
#pragma omp critical
      {
        if (!bad || r < first_bad) first_bad = r;
        bad = true;
      }
      continue;
    }
    hemisphere_basis_eval(order, dirs.row(r).transpose(), out.row(r).data());
  }
  if (bad)
    throw ArgumentError("hemisphere_basis_matrix: direction " + std::to_string(first_bad) +
                        " lies below the horizon (z = " + std::to_string(dirs(first_bad, 2)) + ")");
  return out;
}

}  // namespace icobrdf
