#pragma once
// Progress of a long fit (sample fits, icobrdf/core/fit/sample_fit.hpp; FitOptions::progress of any SOURCE's
// fit, icobrdf/core/fit/spectral_fit.hpp): a stage name and the fraction of it done, in [0, 1]. May be called
// from the calling thread only; never called when empty.
#include <functional>

namespace icobrdf {

using FitProgress = std::function<void(const char* stage, double fraction)>;

}  // namespace icobrdf
