#pragma once
// Orthonormality of the hemisphere basis K to order N by an exact product rule.
//
// 1a. Orthonormality of K to order N by the exact product rule.
//
// Rule: rings = N/2 + 2 Gauss-Legendre nodes in t = rho^2 (exact to degree N + 3 >= N) times
// n_phi = 2N + 2 uniform azimuths (exact for trigonometric degree <= 2N + 1): exact for every K_a K_b.
// Since the rule is a product, G_ab = Rad_ab Az_ab with
//   Rad_ab = sum_k w_k r_a(t_k) r_b(t_k),  r_a = sqrt((n_a + 1)/pi) R_{n_a}^{|l_a|}  (depends on (n, |l|) only)
//   Az_ab  = (2 pi / n_phi) sum_m az_{l_a}(phi_m) az_{l_b}(phi_m)                      (depends on l only),
// both taken from the library's K: r_a from K at (rho_k, phi = 0) (az_l(0) = 1 for l > 0, 1/sqrt(2) for l = 0),
// az_l from K_{|l|}^l on the rim rho = 1 (R_l^l(1) = 1). This needs O(rings + n_phi) evaluations of K
// instead of rings x n_phi, so order 128 (8385 modes) takes well under a second.
// Expected: |delta K_a| <= e_a = kZernikeAbsError sqrt((n_a + 1)/pi) gives, by Cauchy-Schwarz with
// ||K||_2 = 1 and ||delta K||_2 <= sqrt(2 pi) e, |delta G_ab| <= sqrt(2 pi) (e_a + e_b)
// <= 2 sqrt(2) kZernikeAbsError sqrt(N + 1); the sums add (rings + n_phi) eps relative to sums of absolute
// values 1/pi (radial) and pi (azimuthal).
#include <limits>
#include <string>

#include "icobrdf/lab/report_section.hpp"

namespace icobrdf::lab {

struct OrthoResult {
  int order, rings, n_phi, modes;
  double gram_error, bound, seconds;
  double full_gram_error = std::numeric_limits<double>::quiet_NaN();  // unfactorized B^T W B (moderate orders)
};

// The expected bound on max|G - I| of the rule (rings x n_phi) at `order`.
double ortho_bound(int order, int rings, int n_phi);

// Gram error of K to `order` by the factorized rule; with `full`, also B^T W B on the same nodes.
OrthoResult orthonormality(int order, bool full);

// The hard-cases part "Continuous basis to order 128": appends its table (and figure, with a report folder)
// to `md`, s.figures and s.data["orthonormality"].
void add_orthonormality(const SectionOptions& o, ReportSection& s, std::string& md);

}  // namespace icobrdf::lab
