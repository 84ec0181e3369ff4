#pragma once
// The Zernike radial recurrence (icobrdf/core/basis/zernike.hpp) against the closed factorial sum (eq. 3) evaluated in
// quadruple precision (binary128 __float128 where the compiler has it, long double otherwise):
//   R_n^l(rho) = sum_k (-1)^k (n - k)! / (k! ((n + l)/2 - k)! ((n - l)/2 - k)!) rho^(n - 2k).
// The reference's own rounding is at most ~ (n + 4) u_q sum_k |c_k| rho^(n - 2k) (each term carries a few
// roundings of the factorial ratio and the power); it is reported, and a degree counts as checked only
// where it is below 1e-3 of the recurrence's documented error. The same sum in double shows why the
// library does not use it: its error is ~ eps sum_k |c_k| rho^(n - 2k) (cancellation). Errors are absolute.
#include <string>
#include <vector>

#include "icobrdf/lab/report_section.hpp"

namespace icobrdf::lab {

// Documented accuracy of the Zernike recurrence (icobrdf/core/basis/zernike.hpp) and hence of K (icobrdf/core/basis/hemisphere_basis.hpp):
// |delta K_n^l| <= kZernikeAbsError sqrt((n + 1)/pi).
inline constexpr double kZernikeAbsError = 1e-13;

// The largest errors over degrees n_from..n_to, all l, at the sampled rho.
struct ZernikeRow {
  int n_from, n_to;
  double recurrence_error = 0.0, reference_error_bound = 0.0, closed_double_error = 0.0, closed_double_estimate = 0.0;
};

// Degrees 0..n_max in blocks of n_block, at `samples` values of rho evenly spaced in [0, 1] (0 and 1 included).
std::vector<ZernikeRow> zernike_vs_closed_sum(int n_max, int n_block, int samples);

// The hard-cases part "Zernike radial polynomials": appends its table to `md` and its data to s.data["zernike"].
void add_zernike_reference(const SectionOptions& o, ReportSection& s, std::string& md);

}  // namespace icobrdf::lab
