#pragma once
// Any SOURCE as a BrdfModel, for what samples models (`icobrdf lut`): an analytic model (with or without the
// "model:" prefix) as itself; any other SOURCE naming an existing file (a bank material of any
// representation, measured data) through its values (icobrdf/core/models/function_model.hpp; not claimed reciprocal or
// isotropic, so the LUT takes the full path). `label` receives the canonical SOURCE text and, when given,
// `channel_names` the source's channel names (empty when it names none).
#include <memory>
#include <string>
#include <vector>

#include "icobrdf/core/models/brdf_model.hpp"
#include "icobrdf/io/brdf_source.hpp"

namespace icobrdf {

std::shared_ptr<const BrdfModel> model_of_source(const std::string& text, std::string* label,
                                                 std::vector<std::string>* channel_names = nullptr);

// The same for a source already open: an analytic model (its spec() begins with "model:") parsed again from
// its spec, so that its delta parts and isotropy come along; any other source through its values, as above.
std::shared_ptr<const BrdfModel> model_of_open_source(std::shared_ptr<const BrdfSource> source);

}  // namespace icobrdf
