#pragma once
// The "half-angle" and "hybrid" representations: a specular lobe factorized in half-angle coordinates
// (icobrdf/core/models/half_angle_factors.hpp), alone or added to a few Helmholtz modes that carry the body.
//
// half-angle
//   1. isotropy: isotropic = true/false as the scene says; "auto" rotates the held-out pairs about the
//      normal by an azimuth drawn per pair and compares f there (isotropy_defect): isotropic when the
//      metric-weighted relative change is at most kIsotropyShare of the target;
//   2. the quantity factorized is the metric's: q = f cos(theta_i) cos(theta_r) for "cosine", q = f for "f";
//   3. grids from a ladder of increasing size (kIsotropicLadder, kAnisotropicLadder); at each, the rank grows until the weighted node
//      error is within kNodeShare of the target; the first grid whose held-out error meets the target wins;
//      measured data (sources not reciprocal by construction), isotropic lobes: every d grid of the budget
//      grids (icobrdf/pipeline/lobe_budget.hpp), each rank on the largest n_t whose lobe stays below the bytes
//      to beat, ranks until the held-out error stalls, within a work cap per material (kLobeSearchWork or
//      MaterialProblem::lobe_work_cap; node-terms n_t x n_theta_d x n_phi_d x rank, not wall time); the first
//      lobe meeting the target wins at the smallest n_t still meeting it. Short of the target, the
//      lowest-error lobe within the budget is left as the best effort (MaterialProblem::best_efforts) with a
//      note giving its error against bytes (the lowest error, and within half those bytes) and why the search
//      ended;
//   4. the stored form: the grid's lobe, or its channels' shared factors fitted on the same grid, at the
//      narrowest precision (int8, int16, float32, float64) whose held-out error still meets the target
//      (HalfAngleFactors: storage; the error is that of the stored values);
//   5. the record: an all-zero C of order 0 and the lobe; bytes = HalfAngleFactors::bytes + kLobeHeaderBytes.
// hybrid
//   lobe0 = the half-angle candidate's lobe (or the same ladder search when there is none); body = isotropic
//   modes of a low order (kHybridOrders) fitted to f - lobe0 on the first level of the scene that supports
//   it; lobe = half-angle fit of f - body on lobe0's grid, its rank from the target, stored as in step 4. The candidate is the
//   body order with the fewest bytes meeting the target; bytes = the body's IBSSS coefficients (8 per
//   channel + 12 for the indices) + the lobe's bytes. A lobe fitted first keeps the body free of the
//   ringing a low order would take from the peak.
// Both refuse (UnsupportedError) delta sources and CSV samples (no pointwise values) and targets they cannot
// meet. Missing samples of measured data (a MERL table's, its held-out bins included) weigh 0 in the body fit.
#include "icobrdf/pipeline/material_problem.hpp"

namespace icobrdf {

// Metric-weighted relative L2 change of f when both directions of every held-out pair are rotated about the
// normal by one azimuth drawn per pair (seeded: reproducible). 0 for an isotropic BRDF, and for a MERL table
// (isotropic by its format; its held-out pairs are missing from the table fitted).
double isotropy_defect(const BrdfSource& source, const HeldOutErrors& errors);

MaterialCandidate fit_half_angle_candidate(const MaterialProblem& problem);
MaterialCandidate fit_hybrid_candidate(const MaterialProblem& problem);

}  // namespace icobrdf
