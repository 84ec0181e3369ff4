#pragma once
// The smallest tessellation level and expansion order for a material's spectrum.
//
// Levels are tried ascending. At each level one fit is made at the largest order the level supports
// (icobrdf/core/projection/discrete_basis.hpp, capped by order_max or the fixed order); its truncations give the held-out error
// of every lower order. The smallest order meeting the target is then fitted on its own and verified (at the
// top order the fit just made is reused).
// With refit_each_order (scattered samples: the modes are not orthogonal over the samples, so the truncation of
// a least-squares fit is not the fit of the lower order, and a high order the samples cannot bound may fail
// where a lower one succeeds) every order is fitted on its own instead, ascending, from the first order the
// previous levels did not try (the grid only caps the order of such fits); an order whose fit is refused
// (UnsupportedError) is skipped.
// Sources with delta parts have no pointwise error: they are fitted at the fixed order (or the largest order
// allowed) on the first level that supports it.
#include <functional>
#include <string>
#include <vector>

#include "icobrdf/pipeline/fit_source.hpp"
#include "icobrdf/pipeline/held_out.hpp"

namespace icobrdf {

struct LevelOrderSearch {
  FitRequest base;          // grid kind, sampling, isotropic; level and order are set by the search
  std::vector<int> levels;  // tried in this order
  int order_max = 16;
  int fixed_order = -1;     // >= 0: only this order
  bool refit_each_order = false;  // fit every order instead of truncating the top one
  // Told the held-out error of every (level, order) the search measures (optional).
  std::function<void(int level, int order, double error_l2)> seen;
};

struct LevelOrderChoice {
  int level = -1, order = -1;
  int top = -1;             // the largest order fitted on that level
  Spectrum spectrum;        // fitted at (level, order)
  HeldOutError error;       // its held-out error (measured searches)
};

// Delta sources: UnsupportedError when no level supports the order.
LevelOrderChoice fit_at_given_order(const BrdfSource& source, const LevelOrderSearch& search, FitContexts& contexts);

// Measured sources. `accept` sees the choice as soon as it is found (it may change the spectrum); `say` gets
// one progress line per level tried. UnsupportedError naming the best error reached when no (level, order)
// meets the target.
LevelOrderChoice search_level_order(const BrdfSource& source, const LevelOrderSearch& search, FitContexts& contexts,
                                    const HeldOutErrors& errors, double target, const std::string& name,
                                    const std::function<void(LevelOrderChoice&)>& accept,
                                    const std::function<void(const std::string&)>& say);

// Every (level, order) the search considers, for a best effort: `see` gets the spectrum of each order up to
// the level's largest (the truncations of the fit at the largest order; with refit_each_order each order's
// own fit, orders whose fit is refused skipped). Nothing for a level that supports none of the orders.
void each_level_order(const BrdfSource& source, const LevelOrderSearch& search, FitContexts& contexts,
                      const std::function<void(int level, const Spectrum& spectrum)>& see);

}  // namespace icobrdf
