#pragma once
// Isotropic surface-scattering modes I_nm^l (paper eqs. 22-23) and the IBSSS vector.
//
//   I_nm^l = 1/(2 pi) sqrt((n+1)(m+1)/A_nm^l) [R_n^l(rho_i) R_m^l(rho_r) + R_m^l(rho_i) R_n^l(rho_r)] cos(l dphi),
//   A = 4 if n = m and l = 0;  2 if n = m or l = 0 (not both);  1 otherwise,     dphi = phi_i - phi_r,
// with n >= m >= l >= 0, n - l and m - l even. Eq. (23) as printed gives the same A (its extra "n = 0" case
// implies m = l = 0); A follows from orthonormality, see docs/errata.md. The functions of theta_i, theta_r
// and cos(dphi) that are reciprocal ("isotropic" in the paper's sense: invariant under rotation about the
// normal and under reflection in a plane containing it) are exactly their span.
// Library order (= the paper's Table 2): n ascending, then m ascending, then l ascending.
// Count up to total order N: 1, 2, 5, 8, 14, 20, 30, 40, 55 for N = 0..8.
//
// In terms of the general Helmholtz modes (icobrdf/core/basis/helmholtz_modes.hpp), with K_n^{+-l} the hemisphere basis:
//   l = 0, n = m:   I = H(n^0, n^0)
//   l = 0, n > m:   I = H(n^0, m^0)
//   l > 0, n = m:   I = [H(n^l, n^l) + H(n^-l, n^-l)] / sqrt(2)
//   l > 0, n > m:   I = [H(n^l, m^l) + H(n^-l, m^-l)] / sqrt(2)
// because cos(l dphi) = az_l(phi_i) az_l(phi_r) + az_-l(phi_i) az_-l(phi_r) and az_0^2 = 1/2.
// Equivalently each I_k has a coefficient matrix E_k (M x M, symmetric, unit Frobenius norm, disjoint
// supports), I_k = sum_ab (E_k)_ab K_a(w_i) K_b(w_r), and for f with coefficient matrix C:
//   IBSSS a_k = <C, E_k>_F,  isotropic projection P(C) = sum_k a_k E_k (orthogonal, Frobenius),
//   anisotropic energy fraction = ||C - P(C)||_F^2 / ||C||_F^2 (0 for C = 0; a non-reciprocal part of C
//   counts as anisotropic).
#include <Eigen/Core>

#include <vector>

#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf {

struct IsotropicMode {
  int n, m, l;
};

// One term of an isotropic mode in the Helmholtz basis: I = sum weight * H_mode.
struct HelmholtzComponent {
  long long mode;  // index in the Helmholtz library order (helmholtz_mode_index)
  double weight;
};

// Number of isotropic modes with n <= order; ArgumentError outside [0, 128].
int isotropic_mode_count(int order);

// All isotropic modes up to total order N, in Table 2 order.
std::vector<IsotropicMode> isotropic_modes(int order);

// Position of I_nm^l in the library order; ArgumentError unless n >= m >= l >= 0, n-l and m-l even.
int isotropic_mode_index(int n, int m, int l);

// I_nm^l as a combination of Helmholtz modes (1 or 2 terms, orthonormal combination).
std::vector<HelmholtzComponent> isotropic_mode_components(int n, int m, int l);

// IBSSS vector (length isotropic_mode_count(N)) from the M x M coefficient matrix of order N.
Eigen::VectorXd ibsss_from_coefficients(const Eigen::MatrixXd& c);

// Symmetric M x M coefficient matrix of total order `order` from an IBSSS vector of that order.
Eigen::MatrixXd coefficients_from_ibsss(int order, const Eigen::VectorXd& ibsss);

// Orthogonal projection of C onto the isotropic subspace (same size as C).
Eigen::MatrixXd isotropic_projection(const Eigen::MatrixXd& c);

// ||C - P(C)||_F^2 / ||C||_F^2 in [0, 1]; 0 for the zero matrix.
double anisotropic_energy_fraction(const Eigen::MatrixXd& c);

// rows x isotropic_mode_count(order): every isotropic mode at each direction pair, in 1/sr.
Eigen::MatrixXd isotropic_modes_eval(int order, const RowMatrix3d& wi, const RowMatrix3d& wr);

}  // namespace icobrdf
