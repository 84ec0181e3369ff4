#pragma once
// The "modes" representation: a truncated, optionally isotropic and pruned Helmholtz-mode spectrum.
//
//   1. the smallest (level, order) meeting the target (icobrdf/pipeline/level_order_search.hpp), or for a delta
//      source the given order (isotropic unless the scene says isotropic = false);
//   2. isotropic = "auto": the isotropic projection of the chosen fit is kept when it still meets the target;
//      isotropic = true fits the isotropic modes throughout; false keeps the full spectrum;
//   3. pruning (icobrdf/pipeline/pruning.hpp) unless the material says prune = false;
//   4. the record: the spectrum, its IBSSS vector and indices when isotropic; bytes = kept coefficients x
//      (8 bytes per channel + their indices: 3 x 4 bytes (n, m, l) isotropic, 4 x 4 bytes (n, l, m, l')
//      otherwise).
#include "icobrdf/pipeline/material_problem.hpp"

namespace icobrdf {

MaterialCandidate fit_modes_candidate(const MaterialProblem& problem);

// The modes with the lowest held-out error within the material's max_bytes (any size without one): every
// order of every level the search tries (icobrdf/pipeline/level_order_search.hpp each_level_order), as fitted
// and, for isotropic = "auto", its isotropic projection, each with as many of its largest coefficients as
// the budget holds. target_met says whether that error meets the target. UnsupportedError when not even one
// coefficient fits the budget, or for a delta source (no error to minimize).
MaterialCandidate fit_modes_within_budget(const MaterialProblem& problem);

// The record of a spectrum as the bank stores it: with its IBSSS vector and indices when isotropic.
MaterialRecord modes_record(const std::string& name, const Spectrum& spectrum);

// Bytes of `kept` coefficients of a spectrum: 8 per channel + the indices (3 x 4 bytes isotropic, 4 x 4 otherwise).
long long modes_bytes(const Spectrum& spectrum, int kept);

}  // namespace icobrdf
