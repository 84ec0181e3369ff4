#pragma once
// Hemisphere grids that need no mesh, used as baselines and as exact references (icobrdf/core/grid/grid.hpp type).
//
// Polar Gauss grid ("polar-gauss"): the product rule Gauss-Legendre in t = rho^2 = 1 - cos(theta) (rings)
// x uniform azimuth phi_m = 2 pi m / n_phi. Since dOmega = dt dphi under the Lambert map, node weights are
// w_k 2 pi / n_phi. Each node is a one-point "cell". Exact for every product K_a K_b of order <= N when
// rings >= (N + 1)/2 and n_phi >= 2N + 1 (K_a K_b is t^l times a polynomial of degree <= N in t, and a
// trigonometric polynomial of degree <= 2N in phi), so its Gram matrix is I to rounding: the reference
// against which grids are judged.
//
// Latitude-longitude grid ("lat-long"): n_theta bands uniform in theta on [0, pi/2] times n_phi sectors
// uniform in phi; exact solid angles (cos theta_0 - cos theta_1) dphi; cubature per cell = Gauss-Legendre
// with `points` nodes in cos(theta) x `points` nodes in phi (exact weights, degree 2 points - 1 in each).
// Both grids carry the symmetry maps when n_phi is even.
#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf {

Grid build_polar_gauss_grid(int rings, int n_phi);
Grid build_lat_long_grid(int n_theta, int n_phi, int points = 3);

}  // namespace icobrdf
