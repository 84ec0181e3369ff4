#pragma once
// Report section "hard-cases" (`bench sweep`, also `bench hard-cases`): numerical stability on hard cases;
// each measured error is shown next to the expectation it is compared with, derived in the comments of
// the parts and in the report text.
//   1. The continuous basis to order 128: Gram matrix of K by an exact product rule
//      (icobrdf/lab/basis_orthonormality.hpp), and the Zernike recurrence against the closed factorial sum evaluated
//      in quadruple precision (icobrdf/lab/zernike_reference.hpp).
//   2. Delta BRDFs (mirror, retroreflector) on equal-area grids against their analytic spectra, within
//      ||G - I||_2 / (1 - ||G - I||_2).
//   3. Fresnel at grazing and normal incidence: the reflectance against the s/p amplitude formulas, model
//      values finite and reciprocal, reconstruction error near grazing and near normal vs overall.
//   4. Dynamic range 1e4 between a Phong lobe and a Lambertian background: error of each region after
//      projection and reconstruction, negative lobes.
//   5. float32 vs float64 LUTs: the rounding of the LUT through P^T F P and B C B^T, against the bound
//      u ||F||_W / lambda_min(G) (u = 2^-24).
#include "icobrdf/lab/report_section.hpp"

namespace icobrdf::lab {

// Runs the section; ArgumentError when no level is in [1, 6] (the delta BRDFs need one).
ReportSection run_hard_cases(const SectionOptions& o);

}  // namespace icobrdf::lab
