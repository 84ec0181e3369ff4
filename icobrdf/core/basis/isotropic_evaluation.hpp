#pragma once
// Evaluation of an isotropic spectrum from radial rows and cos(l dphi) alone (the fast path of
// evaluate_coefficients, icobrdf/core/spectrum/spectrum_ops.hpp; chosen by pack_spectrum, icobrdf/core/spectrum/spectrum_tile.hpp).
//
// An isotropic C couples K_n^l only with K_m^l of the same l, and its blocks of l and -l are equal
// (icobrdf/core/basis/isotropic_modes.hpp: I_nm^l = [H(n^l, m^l) + H(n^-l, m^-l)] / sqrt(2)). With K_n^l = N_n R_n^|l| az_l,
// N_n = sqrt((n + 1) / pi), az_0 = 1/sqrt(2), and cos(l phi_i) cos(l phi_r) + sin(l phi_i) sin(l phi_r) = cos(l dphi):
//   f(w_i, w_r) = sum_{l = 0..N} cos(l dphi) sum_{n, m} D^l_nm R_n^l(rho_i) R_m^l(rho_r),   dphi = phi_i - phi_r,
//   D^l_nm = N_n N_m C(K_n^l, K_m^l), times 1/2 for l = 0,
// over n, m = l, l + 2, ..., <= N. Per pair: the radial rows of both directions ((N + 2)^2 / 4 values each),
// cos(l dphi) by repeated complex multiplication, and sum_l c_l (c_l + 1) multiply-adds with
// c_l = (N - l) / 2 + 1: 94 at order 8, against 2025 + 2 x 45 basis values for the general form.
// Rounding: that of the basis kernel's recurrences (the same radial rows and the same complex powers, of dphi
// instead of each phi) plus a sum of at most M^2 / 2 products.
#include <Eigen/Core>

namespace icobrdf {

// f[r] for r < n pairs (x, y, z triples wi[3 r ..], wr[3 r ..]; no checks, as hemisphere_basis_block), given
// `blocks`: D^0, D^1, ..., D^N, each c_l x c_l column-major (entry (a, b) for n = l + 2a, m = l + 2b).
// Dispatched to the widest vectors the CPU has; thread-safe.
void isotropic_form_block(int order, const double* blocks, Eigen::Index n, const double* wi, const double* wr, double* f);

}  // namespace icobrdf
