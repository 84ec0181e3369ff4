#pragma once
// Lists of directions and direction pairs in CSV (header row required; degrees unless `radians`):
//   directions:  theta,phi
//   pairs:       theta_i,phi_i,theta_r,phi_r
//   pairs in remote sensing's angles: sza,vza,raa or sza,saa,vza,vaa (icobrdf/io/angle_columns.hpp: raa = 0 on the
//                sun's side; further columns are ignored)
//   pairs in SCATMECH's geometry: thetai,thetas,phis[,rotation]
// theta lies in [-90, 90] degrees (pi/2 in radians); a negative theta is the direction (|theta|, phi + 180 deg),
// the other half of its plane (the goniometer's signed angle). phi, phis, raa and rotation lie within
// kMaxAzimuthTurns turns either way ([-720, 720] degrees, [-4 pi, 4 pi] radians: room for every convention's
// offsets; 1e308 degrees is refused, not evaluated at a meaningless angle).
// SCATMECH geometry (its BRDF_Model angles): w_i, the direction to the source, is (thetai, 180 deg) and
// w_r = (thetas, phis) in the frame where phis = 0 is the forward half of the plane of incidence; a sample
// turned by `rotation` (counterclockwise seen from above) has azimuths phi - rotation in its own frame:
//   w_i = (|thetai|, 180 - rotation [+ 180 if thetai < 0]),  w_r = (|thetas|, phis - rotation [+ 180 if thetas < 0]).
// For isotropic BRDFs (every SCATMECH coefficient file) rotation does not change a value.
// Errors are InputError naming file:line and the offending value (see icobrdf/io/csv.hpp for the format rules).
#include <vector>

#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf {

inline constexpr double kMaxAzimuthTurns = 2.0;

struct DirectionPairs {
  RowMatrix3d wi;          // rows x 3 incident unit vectors
  RowMatrix3d wr;          // rows x 3 remitted unit vectors
  std::vector<int> lines;  // 1-based source line of each row
};

DirectionPairs read_direction_pairs_csv(const std::string& path, bool radians = false);
RowMatrix3d read_directions_csv(const std::string& path, bool radians = false);

}  // namespace icobrdf
