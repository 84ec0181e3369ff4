#pragma once
// Exchanged sample pairs: two samples (w_i, w_r) and (w_i', w_r') with w_i' ~ w_r and w_r' ~ w_i measure the
// same reciprocal value twice (Helmholtz reciprocity), so their difference is the data's own non-reciprocal
// part: measurement noise, or a non-reciprocal instrument. Used for the held-out samples of a bank
// (icobrdf/pipeline/held_out.hpp) and for every sample of a fit (`icobrdf fit`, icobrdf/pipeline/fit_report.hpp).
//
//   asymmetry = |w (f - (f + f^T)/2)| / |w f|     over the samples that have a partner (f^T: the partner's value),
// w = cos(theta_i) cos(theta_r) (metric "cosine", the bank's default) or 1 (metric "f"); the same figure the
// bank reports for sources with values everywhere. When f and f^T carry independent errors of one size, the
// reciprocal part (f + f^T)/2 keeps noise of the size of the antisymmetric part: the asymmetry is then also
// the noise a smooth fit cannot go below (icobrdf/pipeline/material_report.hpp kNoiseMargin).
#include <Eigen/Core>

#include <limits>
#include <vector>

#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf {

// For each row k the row l != k whose w_i is within tolerance_deg of w_r of k and whose w_r is within it of w_i
// of k (the nearest such when several are), or -1. O(S log S + matches) for samples spread over the
// hemisphere (rows sorted by cos theta_i). about_normal: the exchange up to a rotation about the normal
// (theta_i and theta_r exchanged and the same azimuth gap |phi_i - phi_r|, each within tolerance_deg), the
// reciprocal partner of an isotropic surface, as CURET's geometries pair up.
std::vector<Eigen::Index> exchanged_partners(const RowMatrix3d& wi, const RowMatrix3d& wr, double tolerance_deg, bool about_normal = false);

struct ExchangedAsymmetry {
  long long samples = 0;  // samples with a partner (each pair counts twice)
  double asymmetry = std::numeric_limits<double>::quiet_NaN();   // as above; NaN without partners
  double median_relative_difference = std::numeric_limits<double>::quiet_NaN();  // |f - f^T| / ((|f| + |f^T|)/2), over pairs and channels
};

// f: rows x channels; cosine: w = cos(theta_i) cos(theta_r), else 1.
ExchangedAsymmetry exchanged_asymmetry(const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::MatrixXd& f, bool cosine,
                                       double tolerance_deg, bool about_normal = false);

}  // namespace icobrdf
