#pragma once
// Operations on coefficient matrices C (M x M, K basis, ANSI order; see icobrdf/core/spectrum/spectrum.hpp).
#include <Eigen/Core>

#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf {

// f(w_i, w_r) = K(w_i)^T C K(w_r) at many pairs (rows x 3 each): returns rows values [1/sr]. Threads over
// blocks of 192 pairs (basis of both sides by hemisphere_basis_block, then the dispatched tile of
// icobrdf/core/spectrum/spectrum_tile.hpp for the bilinear form: GEMM-shaped for a general C, sparse for an azimuthally
// block-diagonal one such as every isotropic spectrum; rounding bound there; rates in benchmarks/RESULTS.md).
// Each value depends only on its own pair (thread-invariant). ArgumentError for a direction that is not
// finite or has z < -kHorizonSlack (icobrdf/core/basis/horizon.hpp): the first such row of each side is named.
Eigen::VectorXd evaluate_coefficients(const Eigen::MatrixXd& c, int order, const RowMatrix3d& wi, const RowMatrix3d& wr);

// Rotation of the whole BRDF about the normal by `angle` (radians, counter-clockwise seen from above):
// f'(w_i, w_r) = f(R^-1 w_i, R^-1 w_r). In the K basis, K_n^l and K_n^-l mix by a 2 x 2 rotation of angle
// l*angle, so the M x M matrix R is exact and orthogonal; C' = R C R^T.
Eigen::MatrixXd rotation_matrix(int order, double angle);
Eigen::MatrixXd rotate_coefficients(const Eigen::MatrixXd& c, int order, double angle);

// e_b = integral K_b(w) cos(theta) dOmega: non-zero only for K_0^0 (sqrt(2 pi)... see the .cpp derivation)
// and K_2^0. Directional albedo a(w_i) = integral f cos(theta_r) dOmega_r = K(w_i)^T C e.
Eigen::VectorXd cosine_moments(int order);
Eigen::VectorXd spectral_albedo(const Eigen::MatrixXd& c, int order, const RowMatrix3d& wi);

// Rank of a coefficient matrix's reciprocal part: ||C - C^T||_F / ||C||_F / 2 (0 for a symmetric C).
double coefficient_asymmetry(const Eigen::MatrixXd& c);

}  // namespace icobrdf
