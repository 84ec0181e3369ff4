#pragma once
// Lists of directions and direction pairs in CSV (header row required; degrees unless `radians`):
//   directions:  theta,phi
//   pairs:       theta_i,phi_i,theta_r,phi_r
// theta must lie in [0, 90] degrees (the upper hemisphere; pi/2 in radians); phi is any finite angle.
// Errors are InputError naming file:line and the offending value (see io/csv.hpp for the format rules).
#include <vector>

#include "core/grid.hpp"

namespace icobrdf {

struct DirectionPairs {
  RowMatrix3d wi;          // rows x 3 incident unit vectors
  RowMatrix3d wr;          // rows x 3 remitted unit vectors
  std::vector<int> lines;  // 1-based source line of each row
};

DirectionPairs read_direction_pairs_csv(const std::string& path, bool radians = false);
RowMatrix3d read_directions_csv(const std::string& path, bool radians = false);

}  // namespace icobrdf
