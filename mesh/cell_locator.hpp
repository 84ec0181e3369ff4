#pragma once
// CellLocator: direction -> cell index of the hemi-icosahedral tessellation in O(1), without search.
//
// Steps: the face whose centre has the largest dot product with the direction (12 dot products; ties go
// to the face listed first), the face's forward projection (Snyder equal-area, or gnomonic for the
// geodesic grid) to barycentric coordinates, scaled by n = 2^L: (row, column, up/down) of the lattice
// triangle, then a table lookup. The numbering is the one of HemiLattice, identical to the Grid built by
// build_equal_area_grid / build_geodesic_grid at the same level.
//
// Points on a cell boundary (edges, vertices, the pole, the equator) get one of the adjacent cells,
// deterministically: lattice coordinates are floored, up-triangles win ties against down-triangles, and a
// point that rounds to the lower side of the equator gets its mirror cell (which touches it).
#include <Eigen/Core>

#include <array>
#include <string>
#include <vector>

#include "core/grid.hpp"
#include "mesh/gnomonic_projection.hpp"
#include "mesh/snyder_projection.hpp"

namespace icobrdf {

class CellLocator {
 public:
  // kind: "equal-area" or "geodesic"; 0 <= level <= 8. ArgumentError otherwise.
  explicit CellLocator(int level, const std::string& kind = "equal-area");

  // unit_dir: unit vector with z >= -1e-12 (ArgumentError otherwise: |norm - 1| > 1e-10 or z < -1e-12).
  int locate(const Eigen::Vector3d& unit_dir) const;
  // dirs: N x 3 unit vectors; cells resized to N.
  void locate(const RowMatrix3d& dirs, Eigen::VectorXi& cells) const;

  int level() const { return level_; }
  int cells() const { return cells_; }
  const std::string& kind() const { return kind_; }

  // Lattice triangle containing scaled barycentric coordinates (n l1, n l2) of a face: its index within
  // the face (HemiLattice::lattice_index). Clamps to the face.
  static int lattice_triangle(int n, double l1, double l2);

 private:
  int face_of(const Eigen::Vector3d& d) const;
  int locate_unchecked(const Eigen::Vector3d& d) const;

  int level_, n_, cells_;
  std::string kind_;
  bool equal_area_;
  std::array<double, 12> cx_, cy_, cz_;  // face centres
  std::vector<SnyderProjection> snyder_;
  std::vector<GnomonicProjection> gnomonic_;
  std::vector<int> table_;
};

}  // namespace icobrdf
