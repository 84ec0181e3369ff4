#pragma once
// Antisymmetric surface-scattering modes: the complement of the Helmholtz modes (icobrdf/core/basis/helmholtz_modes.hpp)
// in the products K_a(w_i) K_b(w_r). Koenderink & van Doorn (1998, section 2B): the symmetric and the
// antisymmetric combinations together span the space; a reciprocal BRDF has no antisymmetric part, and
// measured data that are not reciprocal can be reproduced by adding these terms.
//
// General (a < b, ANSI indices as in helmholtz_modes.hpp):
//   Z_ab(w_i, w_r) = (K_a(w_i) K_b(w_r) - K_b(w_i) K_a(w_r)) / sqrt(2),
// orthonormal on hemisphere x hemisphere and orthogonal to every Helmholtz mode; there is no Z_aa. Library
// order: b ascending, then a ascending (a < b); count M (M - 1)/2 with M = (N + 1)(N + 2)/2. For a coefficient
// matrix C the coefficient of Z_ab is z_ab = (C_ab - C_ba) / sqrt(2), and the inverse gives the antisymmetric
// A = (C - C^T)/2 with A_ab = z_ab / sqrt(2) = -A_ba, so that C = sym(C) + A and ||A||_F^2 = sum z^2.
//
// Isotropic (functions of theta_i, theta_r and cos(phi_i - phi_r), antisymmetric under w_i <-> w_r): for
// n > m >= l >= 0, n - l and m - l even, with the normalization of the isotropic modes I_nm^l
// (icobrdf/core/basis/isotropic_modes.hpp, A = 2 when l = 0, else 1),
//   J_nm^l = 1/(2 pi) sqrt((n+1)(m+1)/A) [R_n^l(rho_i) R_m^l(rho_r) - R_m^l(rho_i) R_n^l(rho_r)] cos(l dphi),
// (no J_nn^l); library order that of the I_nm^l with n > m. Each J has the coefficient matrix of its I with
// the entries of K_m-type rows (a of order m, b of order n) negated, so the same unit Frobenius norm and
// disjoint supports: the coefficient of J is <C, E_J>_F.
#include <Eigen/Core>

#include <vector>

#include "icobrdf/core/basis/isotropic_modes.hpp"

namespace icobrdf {

// M (M - 1)/2 with M = hemisphere_basis_count(order); ArgumentError for order outside [0, 128].
long long antisymmetric_mode_count(int order);
// Number of isotropic antisymmetric modes (isotropic modes with n > m) up to total order N.
int isotropic_antisymmetric_mode_count(int order);
// The (n, m, l) of each isotropic antisymmetric mode, in library order.
std::vector<IsotropicMode> isotropic_antisymmetric_modes(int order);

// Coefficients z of the antisymmetric part of the M x M matrix C (length M (M - 1)/2).
Eigen::VectorXd antisymmetric_from_coefficients(const Eigen::MatrixXd& c);
// The antisymmetric M x M matrix A of order `order` from such a vector (its length must match).
Eigen::MatrixXd coefficients_from_antisymmetric(int order, const Eigen::VectorXd& z);

// Coefficients of the isotropic antisymmetric modes J of C (length isotropic_antisymmetric_mode_count).
Eigen::VectorXd isotropic_antisymmetric_from_coefficients(const Eigen::MatrixXd& c);
// The antisymmetric M x M matrix of order `order` from such a vector (its length must match).
Eigen::MatrixXd coefficients_from_isotropic_antisymmetric(int order, const Eigen::VectorXd& j);

// Relative Frobenius norm of the antisymmetric part of C: ||C - C^T|| / (2 ||C||); 0 for C = 0.
double antisymmetric_fraction(const Eigen::MatrixXd& c);

}  // namespace icobrdf
