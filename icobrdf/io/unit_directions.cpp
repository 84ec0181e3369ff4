#include "icobrdf/io/unit_directions.hpp"

#include <cmath>
#include <cstdio>

#include "icobrdf/core/basis/horizon.hpp"
#include "icobrdf/core/support/error.hpp"

namespace icobrdf {

void require_unit_directions(const Eigen::Ref<const RowMatrix3d>& w, const std::string& what, bool above_horizon) {
  for (Eigen::Index k = 0; k < w.rows(); ++k) {
    const Eigen::Vector3d v = w.row(k).transpose();
    const double length = v.norm();
    const bool unit = v.allFinite() && std::abs(length - 1.0) <= kUnitDirectionTolerance;
    const bool below = unit && above_horizon && v.z() < -kHorizonSlack;
    if (unit && !below) continue;
    char found[160];
    std::snprintf(found, sizeof found, "row %lld (%.17g, %.17g, %.17g)", static_cast<long long>(k), v.x(), v.y(), v.z());
    char expected[160];
    if (!unit)
      std::snprintf(expected, sizeof expected, "has length %.17g, expected a unit vector (length 1 within %g)", length,
                    kUnitDirectionTolerance);
    else
      std::snprintf(expected, sizeof expected, "lies below the horizon, expected z >= 0");
    throw ArgumentError(what + ": " + found + " " + expected);
  }
}

}  // namespace icobrdf
