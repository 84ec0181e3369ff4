#pragma once
// The orthonormal hemisphere basis K_n^l (paper eq. 13) and its single ANSI index.
//
//   K_n^l(theta, phi) = sqrt((n + 1) / pi) R_n^|l|(rho) az_l(phi),   rho = sqrt(2) sin(theta / 2),
//   az_l = cos(l phi) (l > 0), 1/sqrt(2) (l = 0), -sin(l phi) = sin(|l| phi) (l < 0)   (eq. 5),
// for n >= 0 and l in {-n, -n+2, ..., n}. Orthonormal with the plain solid-angle measure on the upper
// hemisphere: integral K_a K_b dOmega = delta_ab (checked by exact quadrature to order 64 in the tests).
// Single index (ANSI Z80.28 order): j = (n (n + 2) + l) / 2, i.e. n ascending, then l ascending; there are
// M = (N + 1)(N + 2)/2 functions up to total order N, and the functions of order <= N' < N are the first
// M(N') indices. Values are in 1/sqrt(sr); |K_n^l| <= sqrt((n + 1) / pi).
//
// Directions are unit vectors with z >= 0 (normal +z); rho and the azimuth come from the Lambert map
// (icobrdf/core/basis/lambert_map.hpp) and cos(l phi), sin(l phi) from complex multiplication, with no trigonometric call.
// At the pole (rho = 0) the azimuth is taken as 0; every K with l != 0 vanishes there anyway.
// Accuracy: absolute error <= 1e-13 sqrt((n + 1) / pi) (that of the Zernike recurrence) for order <= 128.
#include <Eigen/Core>

#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/core/basis/horizon.hpp"

namespace icobrdf {

// Number of K_n^l with n <= order: (order + 1)(order + 2)/2. Order must be in [0, 128] (ArgumentError).
int hemisphere_basis_count(int order);

// The order N whose count is `count`; ArgumentError if `count` is not (N+1)(N+2)/2 for an N in [0, 128].
int hemisphere_basis_order(int count);

// j = (n (n + 2) + l) / 2; ArgumentError unless n >= 0, |l| <= n, n - l even.
int ansi_index(int n, int l);

struct BasisIndex {
  int n;
  int l;
};

// Inverse of ansi_index; ArgumentError for j < 0.
BasisIndex ansi_to_nl(int j);

// out[j] = K_j(unit_dir) for j < hemisphere_basis_count(order). ArgumentError for an order out of range or a
// direction that is not finite with z >= -kHorizonSlack (z < 0 is taken as 0).
void hemisphere_basis_eval(int order, const Eigen::Vector3d& unit_dir, double* out);

// Two directions at once, for per-sample code (a renderer's modes at w_i and w_r): out_a[j] = K_j(a) and
// out_b[j] = K_j(b) for j < hemisphere_basis_count(order), a and b (x, y, z) triples. The same arithmetic as
// hemisphere_basis_eval, the two directions' chains interleaved; no allocation (a few KB of stack). No checks
// (the caller validates): order in [0, 128]; finite unit vectors with z >= -kHorizonSlack (z < 0 is taken as 0).
void hemisphere_basis_eval_pair(int order, const double* a, const double* b, double* out_a, double* out_b);

// Lane-parallel form for batch code: kBasisLanes directions (x[l], y[l], z[l]) at once, with a factor each:
//   out[j * kBasisLanes + l] (+)= scale[l] * K_j(direction l)   for j < hemisphere_basis_count(order),
// added to out when `accumulate` (cell averages), else written.
// No checks (batch callers validate): order in [0, 128]; unit vectors with z >= -kHorizonSlack (z < 0 is
// taken as 0); scratch holds hemisphere_basis_lanes_scratch(order) doubles. Same recurrences as hemisphere_basis_eval
// (results equal to rounding), laid out so that the compiler vectorizes over the lanes.
inline constexpr int kBasisLanes = 4;
int hemisphere_basis_lanes_scratch(int order);
void hemisphere_basis_eval_lanes(int order, const double* x, const double* y, const double* z, const double* scale,
                                 double* scratch, double* out, bool accumulate = false);

// Block form for batch code, the directions innermost (vectorized over directions in chunks of up to 32, at
// the widest vectors the CPU has: run-time dispatch, icobrdf/core/support/simd_target.hpp):
//   out[j * ld + r] = K_j(direction r)   for r < n, j < hemisphere_basis_count(order),
// i.e. a column-major n x count block with leading dimension ld >= n. dirs holds the n directions as
// (x, y, z) triples (row-major, e.g. RowMatrix3d::data()). No checks (batch callers validate): order in
// [0, 128]; unit vectors with z >= -kHorizonSlack (z < 0 is taken as 0). Same arithmetic as hemisphere_basis_eval
// (results equal to rounding). Thread-safe (per-thread workspace).
void hemisphere_basis_block(int order, Eigen::Index n, const double* dirs, double* out, Eigen::Index ld);

// Weighted sum over directions (a cell's cubature): out[j] = sum_r w[r] K_j(direction r), j < count(order).
// Same layout of dirs and preconditions as hemisphere_basis_block; the summation order is fixed (it depends
// only on n and on the dispatched target's vector width), so results do not depend on threads.
void hemisphere_basis_weighted_sum(int order, Eigen::Index n, const double* dirs, const double* w, double* out);

// Validation for batch callers: the first row of dirs that is not a finite direction with z >= -z_slack,
// or -1 when all are (threads over rows for large inputs; the answer does not depend on threads).
Eigen::Index first_invalid_direction(const RowMatrix3d& dirs, double z_slack = kHorizonSlack);
// The same for n directions stored as (x, y, z) triples from `dirs` (one thread; for a block that is about to
// be evaluated, while it is in cache).
Eigen::Index first_invalid_direction(const double* dirs, Eigen::Index n, double z_slack = kHorizonSlack);

// dirs.rows() x hemisphere_basis_count(order): row r holds every K_j at direction r.
Eigen::MatrixXd hemisphere_basis_matrix(int order, const RowMatrix3d& dirs);

}  // namespace icobrdf
