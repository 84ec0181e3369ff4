// Derivations (K_j = K_n^l, orthonormal on the hemisphere; t = rho^2 = 1 - cos(theta), dOmega = dt dphi).
//
// Lambert, f = albedo/pi. K_0^0 = 1/sqrt(2 pi) and integral K_j dOmega = sqrt(2 pi) delta_j0 (orthogonality to
// the constant). So C_ab = (albedo/pi) sqrt(2 pi)^2 delta_a0 delta_b0 = 2 albedo delta_a0 delta_b0. The IBSSS
// coefficient a_00^0 = C_00 = 2 (the paper prints (1/2) sqrt(2)).
//
// Mirror, g(w_i, w_r) = delta(w_r - mirror(w_i)) in the solid-angle measure (eq. 27: delta(theta_r - theta_i)
// delta(phi_i - phi_r + pi) / sin(theta_r)), mirror(theta, phi) = (theta, phi + pi). Then
// C_ab = integral K_a(w) K_b(theta, phi + pi) dOmega, and K_b(theta, phi + pi) = (-1)^{l_b} K_b(theta, phi)
// by eq. 7, so C_ab = (-1)^{l_b} delta_ab: C = diag((-1)^l), BSSS entries (-1)^l (paper eq. 29: (-1)^k / pi).
//
// Retroreflector, g = delta(w_r - w_i) (eq. 31): C_ab = integral K_a K_b dOmega = delta_ab, C = I
// (paper eq. 34: (1/pi) delta delta).
//
// Minnaert, f = (k+1)/(2 pi) (cos theta_i)^q (cos theta_r)^q, q = k - 1 >= 0. Separable:
// C = (k+1)/(2 pi) c c^T with c_j = integral (1 - t)^q K_j dOmega. The phi integral kills l != 0 and gives
// 2 pi / sqrt(2) for l = 0, so c_{n,0} = sqrt(2 pi (n+1)) integral_0^1 (1-t)^q R_n^0(sqrt t) dt. Odd n has no
// l = 0 term. For n = 2p, R_2p^0(sqrt t) = P_p(2t - 1) (eq. 30), the shifted Legendre polynomial, and
// P_p(2(1-s) - 1) = (-1)^p P_p(2s - 1), so with the classical moment
//   integral_0^1 s^q P_p(2s - 1) ds = q!^2 / ((q+p+1)! (q-p)!)   (p <= q; 0 for p > q, orthogonality),
// c_{2p,0} = sqrt(2 pi (2p+1)) (-1)^p q!^2 / ((q+p+1)! (q-p)!). The spectrum ends at n = 2q = 2(k-1).
// The ratio is evaluated as 1/(q+1) prod_{i<p} (q-i)/(q+i+2), which stays in range for any k.
#include "icobrdf/core/spectrum/analytic_spectra.hpp"

#include <cmath>
#include <string>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"

namespace icobrdf {

Eigen::MatrixXd lambert_coefficients(int order, double albedo) {
  const int m = hemisphere_basis_count(order);
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(m, m);
  c(0, 0) = 2.0 * albedo;
  return c;
}

Eigen::MatrixXd mirror_g_coefficients(int order) {
  const int m = hemisphere_basis_count(order);
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(m, m);
  for (int j = 0; j < m; ++j) c(j, j) = (ansi_to_nl(j).l % 2 == 0) ? 1.0 : -1.0;
  return c;
}

Eigen::MatrixXd retroreflector_g_coefficients(int order) {
  const int m = hemisphere_basis_count(order);
  return Eigen::MatrixXd::Identity(m, m);
}

Eigen::VectorXd cosine_power_projection(int order, int q) {
  if (q < 0) throw ArgumentError("cosine power: exponent must be >= 0, got " + std::to_string(q));
  const int m = hemisphere_basis_count(order);
  Eigen::VectorXd c = Eigen::VectorXd::Zero(m);
  double moment = 1.0 / (q + 1);  // integral_0^1 s^q P_p(2s-1) ds at p = 0
  for (int p = 0; p <= q && 2 * p <= order; ++p) {
    const double sign = (p % 2 == 0) ? 1.0 : -1.0;
    c[ansi_index(2 * p, 0)] = std::sqrt(2.0 * M_PI * (2 * p + 1)) * sign * moment;
    moment *= static_cast<double>(q - p) / (q + p + 2);
  }
  return c;
}

Eigen::MatrixXd minnaert_coefficients(int order, int k) {
  if (k < 1)
    throw ArgumentError("Minnaert: the exponent k must be an integer >= 1 (finite spectrum), got " +
                        std::to_string(k));
  const Eigen::VectorXd c = cosine_power_projection(order, k - 1);
  return (k + 1) / (2.0 * M_PI) * c * c.transpose();
}

}  // namespace icobrdf
