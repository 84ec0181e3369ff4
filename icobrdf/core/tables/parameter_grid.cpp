#include "icobrdf/core/tables/parameter_grid.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "icobrdf/core/support/error.hpp"

namespace icobrdf {

ParameterGrid::ParameterGrid(std::vector<std::vector<double>> axes) : axes_(std::move(axes)) {
  if (axes_.size() > static_cast<size_t>(kMaxGridParameters))
    throw ArgumentError("parameter grid: at most " + std::to_string(kMaxGridParameters) + " parameters, found " +
                        std::to_string(axes_.size()));
  strides_.assign(axes_.size(), 0);
  slices_ = 1;
  for (int d = static_cast<int>(axes_.size()) - 1; d >= 0; --d) {
    const auto& a = axes_[static_cast<size_t>(d)];
    if (a.empty()) throw ArgumentError("parameter grid: axis " + std::to_string(d) + " has no node");
    for (size_t k = 0; k < a.size(); ++k) {
      if (!std::isfinite(a[k])) throw ArgumentError("parameter grid: axis " + std::to_string(d) + " node " + std::to_string(k) + " is not finite");
      if (k > 0 && !(a[k] > a[k - 1]))
        throw ArgumentError("parameter grid: axis " + std::to_string(d) + " nodes must increase strictly, node " + std::to_string(k) +
                            " is " + std::to_string(a[k]) + " after " + std::to_string(a[k - 1]));
    }
    strides_[static_cast<size_t>(d)] = slices_;
    slices_ *= static_cast<std::int64_t>(a.size());
  }
}

SliceBlend ParameterGrid::blend(const double* params) const {
  SliceBlend b;
  b.count = 1;
  b.slice[0] = 0;
  b.weight[0] = 1.0;
  for (size_t d = 0; d < axes_.size(); ++d) {
    const auto& a = axes_[d];
    if (a.size() == 1) continue;
    const double x = params[d];
    // Largest i with a[i] < x, clamped to [0, n - 2].
    const auto it = std::lower_bound(a.begin(), a.end(), x);  // first a[k] >= x
    std::int64_t i = static_cast<std::int64_t>(it - a.begin()) - 1;
    i = std::clamp<std::int64_t>(i, 0, static_cast<std::int64_t>(a.size()) - 2);
    const double v0 = a[static_cast<size_t>(i)], v1 = a[static_cast<size_t>(i + 1)];
    double t = (x - v0) / (v1 - v0);
    t = std::isnan(t) ? 0.0 : std::clamp(t, 0.0, 1.0);
    const std::int64_t s = strides_[d];
    const int n = b.count;
    for (int k = 0; k < n; ++k) {
      b.slice[static_cast<size_t>(n + k)] = b.slice[static_cast<size_t>(k)] + (i + 1) * s;
      b.weight[static_cast<size_t>(n + k)] = b.weight[static_cast<size_t>(k)] * t;
      b.slice[static_cast<size_t>(k)] += i * s;
      b.weight[static_cast<size_t>(k)] *= 1.0 - t;
    }
    b.count = 2 * n;
  }
  return b;
}

}  // namespace icobrdf
