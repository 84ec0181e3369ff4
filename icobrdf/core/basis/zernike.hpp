#pragma once
// Zernike radial polynomials R_n^l(rho) on [0, 1] (paper eq. 3), for 0 <= l <= n, n - l even.
//
// Normalization: the classical one, R_n^l(1) = 1, |R_n^l(rho)| <= 1 on [0, 1],
//   integral_0^1 R_n^l R_m^l 2 rho drho = delta_nm / (n + 1).
//
// Packed layout of "all (n, l) up to order N": row n holds l = n mod 2, n mod 2 + 2, ..., n (floor(n/2) + 1
// values), rows in ascending n. Row n starts at floor((n+1)^2 / 4); the total is floor((N+2)^2 / 4)
// (4225 for N = 128).
//
// Method: the three-term recurrence in (n, l) (Shakibaei & Paramesran, Opt. Lett. 38, 2487 (2013))
//   R_n^l = rho (R_{n-1}^{|l-1|} + R_{n-1}^{l+1}) - R_{n-2}^l,   R_n^n = rho^n,   R_{n-1}^{n} := 0,
// which only combines values bounded by 1, so rounding errors stay at the level of a few ulps times n.
// The closed factorial sum (eq. 3) cancels catastrophically (its coefficients reach 1e37 at n = 128) and
// is not used. Measured accuracy (tests/core/basis/test_zernike.cpp, against 100-digit references): absolute
// error <= 1e-13 for all n <= 128 and rho in [0, 1], including rho = 0 and rho = 1.
//
// Arguments outside the domain (order < 0, (n, l) not a valid pair, rho outside [0, 1]) throw ArgumentError.
namespace icobrdf {

// Largest order the library supports for Zernike polynomials and everything built on them.
inline constexpr int kMaxZernikeOrder = 128;

// Number of (n, l) pairs with 0 <= l <= n <= order, n - l even: floor((order + 2)^2 / 4).
int zernike_radial_count(int order);

// Position of R_n^l in the packed layout (independent of the order of the array it sits in).
int zernike_radial_index(int n, int l);

// All R_n^l(rho) for n <= order, written packed to out[0 .. zernike_radial_count(order)).
void zernike_radial_all(int order, double rho, double* out);

// One R_n^l(rho) (evaluates the recurrence along the needed rows; O(n^2) work).
double zernike_radial(int n, int l, double rho);

}  // namespace icobrdf
