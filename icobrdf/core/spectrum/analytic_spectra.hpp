#pragma once
// Closed-form coefficient matrices C (M x M, K basis in ANSI order, icobrdf/core/spectrum/spectrum.hpp) of BRDFs whose
// spectrum is known exactly; references for the discrete engine. C_ab = integral integral f K_a(w_i) K_b(w_r)
// (or the same with g = f cos(theta_i), eq. 16, for the delta-like BRDFs). Derivations in
// analytic_spectra.cpp and docs/errata.md.
//
//   lambert_coefficients      f = albedo / pi:          C_00 = 2 albedo, all else 0
//   mirror_g_coefficients     g of eq. 27 (mirror):     C = diag((-1)^l)  (l of K_j = K_n^l)
//   retroreflector_g_coeffs   g of eq. 31 (retro):      C = identity
//   minnaert_coefficients     f of eq. 35, integer k:   C = (k+1)/(2 pi) c c^T, c supported on l = 0, n <= 2(k-1)
//
// Orders outside [0, 128] and k < 1 throw ArgumentError.
#include <Eigen/Core>

namespace icobrdf {

Eigen::MatrixXd lambert_coefficients(int order, double albedo = 1.0);
Eigen::MatrixXd mirror_g_coefficients(int order);
Eigen::MatrixXd retroreflector_g_coefficients(int order);

// Minnaert (Opik) f = (k+1)/(2 pi) (cos theta_i cos theta_r)^(k-1) with integer k >= 1 (k = 1 is Lambert).
Eigen::MatrixXd minnaert_coefficients(int order, int k);

// The hemisphere projection c_j = integral (cos theta)^q K_j dOmega (length M), the factor of the Minnaert C.
// Nonzero only for l = 0 and n = 2p <= 2q:
//   c_{2p,0} = sqrt(2 pi (2p+1)) (-1)^p q!^2 / ((q+p+1)! (q-p)!).
Eigen::VectorXd cosine_power_projection(int order, int q);

}  // namespace icobrdf
