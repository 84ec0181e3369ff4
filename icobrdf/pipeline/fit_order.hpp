#pragma once
// The order of a fit when none is given: `icobrdf fit` without --order and icobrdf.fit(order=None) in Python
// ask the same question and get the same answer here.
#include <optional>

#include "icobrdf/io/brdf_source.hpp"

namespace icobrdf {

// The order of a fit of a source that does not choose its own.
inline constexpr int kDefaultFitOrder = 8;

// FitRequest::order (icobrdf/pipeline/fit_source.hpp) for `source`: the order given; without one, kChooseOrder
// for the sources that choose their own (scattered samples, icobrdf/io/measured_sources.hpp chooses_order: order
// and model class by cross-validation), else kDefaultFitOrder. Defined in fit_source.cpp.
int fit_order_for(const BrdfSource& source, std::optional<int> order);

}  // namespace icobrdf
