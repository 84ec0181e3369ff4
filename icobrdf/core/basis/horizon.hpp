#pragma once
// The horizon's slack: one tolerance shared by every check of "is this direction in the upper hemisphere".
//
// Directions computed on the equator (theta = 90 degrees from degrees, normalizations, cubature points of
// half cells) carry a rounding-sized z of either sign, about 1e-16. A z in [-kHorizonSlack, 0) therefore
// counts as on the horizon (z = 0) and below that as below the horizon: models give f = 0 there
// (icobrdf/core/models/brdf_model.hpp), the Lambert map and the basis refuse it (icobrdf/core/basis/lambert_map.hpp,
// icobrdf/core/basis/hemisphere_basis.hpp), and so does cell lookup (icobrdf/mesh/cell_locator.hpp). The horizon's image on the
// Lambert disk is the unit circle, so the same slack bounds the disk radius: rho (or |p|^2) up to
// 1 + kHorizonSlack is taken as on the rim (icobrdf/core/basis/zernike.cpp, icobrdf/core/basis/lambert_map.cpp). 1e-12 is far above
// that rounding and far below any real displacement from the horizon.
namespace icobrdf {

inline constexpr double kHorizonSlack = 1e-12;

}  // namespace icobrdf
