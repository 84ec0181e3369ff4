#pragma once
// Pruning a spectrum: its coefficients (BSSS, or IBSSS when isotropic, and the antisymmetric ones of a spectrum
// fitted with reciprocal = false, icobrdf/core/basis/antisymmetric_modes.hpp) dropped smallest first while the
// held-out error stays within the target.
#include "icobrdf/core/spectrum/spectrum.hpp"
#include "icobrdf/pipeline/held_out.hpp"

namespace icobrdf {

struct PruneResult {
  int kept = 0, total = 0;  // coefficients kept / in the full (B|IB)SSS vector
  bool pruned = false;      // the spectrum was replaced by its pruned version
  HeldOutError error;       // of the pruned spectrum (when pruned)
};

// Smallest number of kept coefficients meeting `target`, by bisection on the (nearly monotone) error; the
// result is verified, and the full spectrum (which meets the target) is the fallback. Coefficients rank by
// their largest magnitude over the channels. `spectrum` is replaced by its pruned version when that meets the
// target.
// Whether some channel's C is not exactly symmetric (a fit that kept its antisymmetric terms; a reciprocal fit
// is symmetrized exactly).
bool has_antisymmetric_terms(const Spectrum& spectrum);
// Coefficients of the full vector: the (B|IB)SSS modes, plus the (isotropic) antisymmetric ones when it has them.
int coefficient_total(const Spectrum& spectrum);

PruneResult prune_coefficients(Spectrum& spectrum, const HeldOutErrors& errors, double target);

// The spectrum with its `kept` largest coefficients only (ranked as above; all of them when kept >= total),
// and its held-out error.
PruneResult keep_largest(Spectrum& spectrum, const HeldOutErrors& errors, int kept);

}  // namespace icobrdf
