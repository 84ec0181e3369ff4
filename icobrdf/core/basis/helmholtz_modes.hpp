#pragma once
// General (anisotropic) Helmholtz surface-scattering modes (paper eqs. 17-21) and the BSSS vector.
//
// A mode is a pair of hemisphere-basis indices a <= b (ANSI, icobrdf/core/basis/hemisphere_basis.hpp), K_a = K_n^l,
// K_b = K_m^l':
//   H_ab(w_i, w_r) = (K_a(w_i) K_b(w_r) + K_b(w_i) K_a(w_r)) / sqrt(2)   (a < b),
//   H_aa(w_i, w_r) =  K_a(w_i) K_a(w_r),
// orthonormal on hemisphere x hemisphere (dOmega_i dOmega_r) and spanning the reciprocal functions.
// Library order of the modes: b ascending, then a ascending; mode (a, b) has index b (b + 1)/2 + a. The
// modes of order <= N' < N are therefore the first M'(M'+1)/2 modes of order N (truncation is a prefix).
// Count up to total order N: M (M + 1)/2 with M = (N + 1)(N + 2)/2 (21, 120, 1035 for N = 2, 4, 8).
//
// Coefficients. With C_ab = integral integral f K_a(w_i) K_b(w_r) (M x M, icobrdf/core/spectrum/spectrum.hpp), the BSSS
// coefficient of mode (a, b) is the projection of f onto H_ab:
//   a_ab = (C_ab + C_ba) / sqrt(2)  (a < b; = sqrt(2) C_ab for symmetric C),   a_aa = C_aa,
// so a non-reciprocal C is projected onto its reciprocal (symmetric) part, and sum_k a_k^2 = ||sym(C)||_F^2.
// The inverse gives the symmetric C with C_ab = C_ba = a_ab / sqrt(2), C_aa = a_aa.
#include <Eigen/Core>

#include <vector>

#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf {

struct HelmholtzMode {
  int a, b;    // ANSI indices, a <= b
  int n, l;    // K_a = K_n^l
  int m, lp;   // K_b = K_m^lp
};

// M (M + 1)/2 with M = hemisphere_basis_count(order); ArgumentError for order outside [0, 128].
long long helmholtz_mode_count(int order);

// Index of the mode {a, b} (in either order) in the library order; ArgumentError for negative indices.
long long helmholtz_mode_index(int a, int b);

// The mode at library index k (inverse of helmholtz_mode_index, independent of the order); ArgumentError for k < 0.
HelmholtzMode helmholtz_mode_at(long long k);

// All modes up to total order N in the library order; size helmholtz_mode_count(order) (35 million at N = 128,
// 24 bytes each: list only what you need).
std::vector<HelmholtzMode> helmholtz_modes(int order);

// BSSS vector (length M (M+1)/2) from the M x M coefficient matrix C (any square size M that is a basis count).
Eigen::VectorXd bsss_from_coefficients(const Eigen::MatrixXd& c);

// Symmetric M x M coefficient matrix from a BSSS vector (its length must be a mode count).
Eigen::MatrixXd coefficients_from_bsss(const Eigen::VectorXd& bsss);

// rows x helmholtz_mode_count(order): the value of every mode at each direction pair (w_i row r, w_r row r),
// unit vectors with z >= 0, in 1/sr. wi and wr must have the same number of rows (ArgumentError).
Eigen::MatrixXd helmholtz_modes_eval(int order, const RowMatrix3d& wi, const RowMatrix3d& wr);
// The same written into `out` (rows x helmholtz_mode_count(order), ArgumentError otherwise), for callers that
// reuse one buffer over many blocks of pairs.
void helmholtz_modes_eval(int order, const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out);

}  // namespace icobrdf
