#include "icobrdf/core/basis/hemisphere_basis.hpp"

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <string>
#include <vector>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/huge_pages.hpp"
#include "icobrdf/core/basis/zernike.hpp"

namespace icobrdf {

namespace {

// sqrt((n + 1) / pi) for n <= 128.
const std::array<double, kMaxZernikeOrder + 1> kNorm = [] {
  std::array<double, kMaxZernikeOrder + 1> t{};
  for (int n = 0; n <= kMaxZernikeOrder; ++n) t[static_cast<size_t>(n)] = std::sqrt((n + 1) / M_PI);
  return t;
}();

void check_basis_order(int order) {
  if (order < 0 || order > kMaxZernikeOrder)
    throw ArgumentError("expansion order " + std::to_string(order) + " out of range: expected 0 <= order <= " +
                        std::to_string(kMaxZernikeOrder));
}

}  // namespace

int hemisphere_basis_count(int order) {
  check_basis_order(order);
  return (order + 1) * (order + 2) / 2;
}

int hemisphere_basis_order(int count) {
  for (int n = 0; n <= kMaxZernikeOrder; ++n)
    if ((n + 1) * (n + 2) / 2 == count) return n;
  throw ArgumentError("hemisphere basis: " + std::to_string(count) +
                      " is not (N+1)(N+2)/2 for any order N in [0, " + std::to_string(kMaxZernikeOrder) + "]");
}

int ansi_index(int n, int l) {
  if (n < 0 || l < -n || l > n || (n - l) % 2 != 0)
    throw ArgumentError("mode index: need n >= 0, |l| <= n, n - l even, got n = " + std::to_string(n) +
                        ", l = " + std::to_string(l));
  return (n * (n + 2) + l) / 2;
}

BasisIndex ansi_to_nl(int j) {
  if (j < 0) throw ArgumentError("mode index: index must be >= 0, got " + std::to_string(j));
  int n = static_cast<int>((std::sqrt(8.0 * j + 1.0) - 1.0) / 2.0);
  while (n * (n + 1) / 2 > j) --n;            // guard the floating-point estimate
  while ((n + 1) * (n + 2) / 2 <= j) ++n;
  return {n, 2 * (j - n * (n + 1) / 2) - n};
}

namespace {

inline int radial_start(int n) { return (n + 1) * (n + 1) / 4; }

// K_j at one direction (V = double: hemisphere_basis_eval) or two (V = Pair, one direction per lane:
// hemisphere_basis_eval_pair), no argument checks (order valid). The two directions' arithmetic is one vector
// operation per step; V's explicit lanes also keep the compiler from vectorizing the short loops over l, whose
// set-up costs more than their work at low orders (a pair at order 2, callgrind: 316 instructions; two single
// evaluations of the former code, which kept the whole radial triangle, about 900; the loops vectorized over l
// with lanes as arrays, 836).
// One pass over n: the radial row n from rows n - 1 and n - 2 (three rows kept, not the whole triangle, so the
// frame is a few KB), cos(n phi) and sin(n phi) by one complex multiplication, then row n of the output.
using Pair = double __attribute__((vector_size(16)));

inline void store(double* const* out, int j, double v) { out[0][j] = v; }
inline void store(double* const* out, int j, Pair v) {
  out[0][j] = v[0];
  out[1][j] = v[1];
}

// rho = |p| on the Lambert disk (rho^2 = 1 - cos(theta), without cancellation: lambert_map.hpp) and the
// azimuth's (cos, sin) from (x, y) without trigonometry, (1, 0) at the pole; z < 0 is taken as 0.
inline void polar(double x, double y, double z, double& rho, double& c1, double& s1) {
  const double h2 = x * x + y * y;
  const double r2 = h2 / (1.0 + (z < 0.0 ? 0.0 : z));
  rho = std::sqrt(r2 > 1.0 ? 1.0 : r2);
  const double s = std::sqrt(h2);
  c1 = s > 0.0 ? x / s : 1.0;
  s1 = s > 0.0 ? y / s : 0.0;
}

template <class V>
void eval_points(int order, V rho, V c1, V s1, double* const* out) {
  constexpr int kRow = kMaxZernikeOrder / 2 + 1;  // entries of the longest radial row
  V rad[3][kRow];                                 // rows n, n - 1, n - 2 in turn: [i] = R_n^{n mod 2 + 2i}
  V cosl[kMaxZernikeOrder + 1], sinl[kMaxZernikeOrder + 1];  // cos(l phi) (l = 0: 1/sqrt(2)), sin(l phi)
  const V zero = rho - rho;
  cosl[0] = zero + M_SQRT1_2;
  sinl[0] = zero;
  V *cur = rad[0], *prev = rad[2], *prev2 = rad[1];
  for (int n = 0; n <= order; ++n) {
    if (n > 0) {  // row n - 1 becomes prev, n - 2 prev2, and n - 3's storage takes row n
      V* free_row = prev2;
      prev2 = prev, prev = cur, cur = free_row;
    }
    const int last = n / 2;
    if (n == 0) {
      cur[0] = zero + 1.0;
    } else if (n == 1) {
      cur[0] = rho;
    } else if (n % 2 == 0) {  // l = 2i from l - 1 and l + 1 of row n - 1 (at l = 0 both are l = 1)
      cur[0] = 2.0 * rho * prev[0] - prev2[0];
      for (int i = 1; i < last; ++i) cur[i] = rho * (prev[i - 1] + prev[i]) - prev2[i];
      cur[last] = rho * prev[last - 1];
    } else {  // l = 2i + 1 from l - 1 = 2i and l + 1 = 2i + 2 of row n - 1
      for (int i = 0; i < last; ++i) cur[i] = rho * (prev[i] + prev[i + 1]) - prev2[i];
      cur[last] = rho * prev[last];
    }
    if (n > 0) {  // cos(n phi) + i sin(n phi) = (cos((n - 1) phi) + i sin((n - 1) phi)) (cos phi + i sin phi)
      const V c = n == 1 ? zero + 1.0 : cosl[n - 1];
      cosl[n] = c * c1 - sinl[n - 1] * s1;
      sinl[n] = sinl[n - 1] * c1 + c * s1;
    }
    // K_n^l for l = -n, -n + 2, ..., n: az_l = sin(|l| phi) for l < 0, cos(l phi) (1/sqrt(2) at l = 0) for l >= 0.
    const double norm = kNorm[static_cast<size_t>(n)];
    const int neg = (n + 1) / 2, base = n * (n + 1) / 2;
    for (int e = 0; e < neg; ++e) store(out, base + e, norm * cur[last - e] * sinl[n - 2 * e]);  // |l| = n - 2e
    for (int e = neg; e <= n; ++e) store(out, base + e, norm * cur[e - neg] * cosl[2 * (e - neg) + n % 2]);
  }
}

}  // namespace

int hemisphere_basis_lanes_scratch(int order) {
  check_basis_order(order);
  return (radial_start(order + 1) + 2 * order + 1) * kBasisLanes;
}

// The recurrences of eval_points, lanes innermost so that they vectorize (kept for batch callers and tests: the
// library's own batches use hemisphere_basis_block).
void hemisphere_basis_eval_lanes(int order, const double* x, const double* y, const double* z, const double* w,
                                 double* scratch, double* __restrict out, bool accumulate) {
  double* __restrict rad = scratch;
  double* __restrict az = scratch + radial_start(order + 1) * kBasisLanes;
  const double* norm = kNorm.data();
  alignas(32) double rho[kBasisLanes], c1[kBasisLanes], s1[kBasisLanes], c[kBasisLanes], sn[kBasisLanes];
  for (int k = 0; k < kBasisLanes; ++k) polar(x[k], y[k], z[k], rho[k], c1[k], s1[k]);
  // Zernike radial rows (packed as in icobrdf/core/basis/zernike.hpp), times kBasisLanes.
  for (int k = 0; k < kBasisLanes; ++k) {
    rad[k] = 1.0;
    if (order > 0) rad[kBasisLanes + k] = rho[k];
  }
  for (int n = 2; n <= order; ++n) {
    double* __restrict cur = rad + radial_start(n) * kBasisLanes;
    const double* __restrict prev = rad + radial_start(n - 1) * kBasisLanes;
    const double* __restrict prev2 = rad + radial_start(n - 2) * kBasisLanes;
    const int last = n / 2;
    if (n % 2 == 0) {
      for (int k = 0; k < kBasisLanes; ++k) cur[k] = 2.0 * rho[k] * prev[k] - prev2[k];
      for (int i = 1; i < last; ++i)
        for (int k = 0; k < kBasisLanes; ++k)
          cur[i * kBasisLanes + k] = rho[k] * (prev[(i - 1) * kBasisLanes + k] + prev[i * kBasisLanes + k]) - prev2[i * kBasisLanes + k];
      for (int k = 0; k < kBasisLanes; ++k) cur[last * kBasisLanes + k] = rho[k] * prev[(last - 1) * kBasisLanes + k];
    } else {
      for (int i = 0; i < last; ++i)
        for (int k = 0; k < kBasisLanes; ++k)
          cur[i * kBasisLanes + k] = rho[k] * (prev[i * kBasisLanes + k] + prev[(i + 1) * kBasisLanes + k]) - prev2[i * kBasisLanes + k];
      for (int k = 0; k < kBasisLanes; ++k) cur[last * kBasisLanes + k] = rho[k] * prev[last * kBasisLanes + k];
    }
  }
  // Weighted azimuthal factors: az[(order + l) kBasisLanes + lane] = w az_l(phi), by complex multiplication.
  for (int k = 0; k < kBasisLanes; ++k) {
    az[order * kBasisLanes + k] = w[k] * M_SQRT1_2;
    c[k] = 1.0;
    sn[k] = 0.0;
  }
  for (int l = 1; l <= order; ++l)
    for (int k = 0; k < kBasisLanes; ++k) {
      const double c_next = c[k] * c1[k] - sn[k] * s1[k];
      sn[k] = sn[k] * c1[k] + c[k] * s1[k];
      c[k] = c_next;
      az[(order + l) * kBasisLanes + k] = w[k] * c[k];
      az[(order - l) * kBasisLanes + k] = w[k] * sn[k];
    }
  for (int n = 0; n <= order; ++n) {
    const double nn = norm[n];
    const double* row = rad + radial_start(n) * kBasisLanes;
    double* o = out + n * (n + 1) / 2 * kBasisLanes;
    const double* a = az + (order - n) * kBasisLanes;  // a[2e kBasisLanes] = w az_l for l = -n + 2e
    const int neg = (n + 1) / 2;
    if (accumulate) {
      for (int e = 0; e < neg; ++e)
        for (int k = 0; k < kBasisLanes; ++k) o[e * kBasisLanes + k] += nn * row[(n / 2 - e) * kBasisLanes + k] * a[2 * e * kBasisLanes + k];
      for (int e = neg; e <= n; ++e)
        for (int k = 0; k < kBasisLanes; ++k) o[e * kBasisLanes + k] += nn * row[(e - neg) * kBasisLanes + k] * a[2 * e * kBasisLanes + k];
    } else {
      for (int e = 0; e < neg; ++e)
        for (int k = 0; k < kBasisLanes; ++k) o[e * kBasisLanes + k] = nn * row[(n / 2 - e) * kBasisLanes + k] * a[2 * e * kBasisLanes + k];
      for (int e = neg; e <= n; ++e)
        for (int k = 0; k < kBasisLanes; ++k) o[e * kBasisLanes + k] = nn * row[(e - neg) * kBasisLanes + k] * a[2 * e * kBasisLanes + k];
    }
  }
}

void hemisphere_basis_eval(int order, const Eigen::Vector3d& unit_dir, double* out) {
  check_basis_order(order);
  if (first_invalid_direction(unit_dir.data(), 1) >= 0)
    throw ArgumentError("hemisphere_basis_eval: direction (" + std::to_string(unit_dir.x()) + ", " + std::to_string(unit_dir.y()) + ", " +
                        std::to_string(unit_dir.z()) + ") is not a finite direction with z >= 0");
  double rho, c1, s1;
  polar(unit_dir.x(), unit_dir.y(), unit_dir.z(), rho, c1, s1);
  eval_points<double>(order, rho, c1, s1, &out);
}

void hemisphere_basis_eval_pair(int order, const double* a, const double* b, double* out_a, double* out_b) {
  double rho_a, c1_a, s1_a, rho_b, c1_b, s1_b;
  polar(a[0], a[1], a[2], rho_a, c1_a, s1_a);
  polar(b[0], b[1], b[2], rho_b, c1_b, s1_b);
  double* out[2] = {out_a, out_b};
  eval_points<Pair>(order, Pair{rho_a, rho_b}, Pair{c1_a, c1_b}, Pair{s1_a, s1_b}, out);
}

Eigen::Index first_invalid_direction(const double* dirs, Eigen::Index n, double z_slack) {
  // Blocks of rows are checked without branches (|v| <= DBL_MAX is false for inf and NaN, and so is
  // z >= -slack for NaN); only a block that holds a bad row is searched row by row.
  constexpr Eigen::Index kBlock = 256;
  auto bad = [&](Eigen::Index r) {
    const double x = dirs[3 * r], y = dirs[3 * r + 1], z = dirs[3 * r + 2];
    return !(std::abs(x) <= DBL_MAX && std::abs(y) <= DBL_MAX && std::abs(z) <= DBL_MAX && z >= -z_slack);
  };
  for (Eigen::Index r0 = 0; r0 < n; r0 += kBlock) {
    const Eigen::Index r1 = std::min(n, r0 + kBlock);
    int any = 0;
    for (Eigen::Index r = r0; r < r1; ++r) any |= static_cast<int>(bad(r));
    if (any)
      for (Eigen::Index r = r0; r < r1; ++r)
        if (bad(r)) return r;
  }
  return -1;
}

Eigen::Index first_invalid_direction(const RowMatrix3d& dirs, double z_slack) {
  const Eigen::Index rows = dirs.rows();
  constexpr Eigen::Index kBlock = 4096;
  const Eigen::Index blocks = (rows + kBlock - 1) / kBlock;
  Eigen::Index first = rows;
#pragma omp parallel for schedule(static) reduction(min : first) if (rows > 100000)
  for (Eigen::Index b = 0; b < blocks; ++b) {
    const Eigen::Index r0 = b * kBlock;
    if (r0 >= first) continue;
    const Eigen::Index r = first_invalid_direction(dirs.data() + 3 * r0, std::min(kBlock, rows - r0), z_slack);
    if (r >= 0) first = std::min(first, r0 + r);
  }
  return first < rows ? first : -1;
}

Eigen::MatrixXd hemisphere_basis_matrix(int order, const RowMatrix3d& dirs) {
  const int count = hemisphere_basis_count(order);
  const Eigen::Index rows = dirs.rows();
  // Validate up front: nothing may throw inside the parallel loop.
  if (const Eigen::Index r = first_invalid_direction(dirs); r >= 0)
    throw ArgumentError("hemisphere basis: direction " + std::to_string(r) + " = (" + std::to_string(dirs(r, 0)) + ", " +
                        std::to_string(dirs(r, 1)) + ", " + std::to_string(dirs(r, 2)) + ") is not a finite direction with z >= 0");
  Eigen::MatrixXd out(rows, count);
  advise_huge_pages(out.data(), sizeof(double) * static_cast<size_t>(out.size()));
  // Blocks of rows go straight into the column-major result (each mode's values for a block are contiguous).
  constexpr Eigen::Index kBlock = 256;
  const Eigen::Index blocks = (rows + kBlock - 1) / kBlock;
#pragma omp parallel for schedule(static) if (rows * count > 200000)
  for (Eigen::Index b = 0; b < blocks; ++b) {
    const Eigen::Index r0 = b * kBlock, nr = std::min(kBlock, rows - r0);
    hemisphere_basis_block(order, nr, dirs.data() + 3 * r0, out.data() + r0, rows);
  }
  return out;
}

}  // namespace icobrdf
