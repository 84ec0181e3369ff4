#pragma once
// Grid: the plain value type a tessellation of the upper hemisphere hands to core.
//
// No mesh-library types appear here; mesh/ builds it (equal-area hemi-icosahedron, geodesic baseline)
// and benchmarks may build other kinds (latitude-longitude, polar Gauss) without a mesh.
//
// Conventions: surface normal +z; every direction is a unit vector with z >= 0. Solid angles in sr.
// Shapes (C = number of cells, Q = total cubature points):
//   directions        C x 3   representative direction of each cell (unit vector)
//   solid_angles      C       exact solid angle of each cell [sr]; sum = 2 pi for a full hemisphere
//   cubature_offsets  C + 1   points of cell c are rows [offsets[c], offsets[c+1]) of cubature_points
//   cubature_points   Q x 3   unit vectors on the cell
//   cubature_weights  Q       [sr]; the weights of one cell sum to its solid angle
//   vertices          V x 3   unit vectors (empty for grids that are not triangle meshes)
//   faces             C x 3   vertex ids of each triangular cell, counter-clockwise seen from outside
//   neighbours        C x 3   cell across the edge opposite faces(c, k); -1 on the hemisphere boundary
//   is_half           C       1 for a cell cut in half by the equator
//   rotate_pi         C       cell containing the image under rotation by pi about +z (mirror partner)
//   mirror_xz         C       cell containing the image under the mirror y -> -y
//   mirror_yz         C       cell containing the image under the mirror x -> -x
// The symmetry maps are empty when the grid is not invariant under them.
#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

#include "icobrdf/core/grid/row_matrix.hpp"

namespace icobrdf {

// What built a grid. Files hold its name (to_string), and Spectrum::grid_kind the same name.
enum class GridKind {
  Custom,      // "custom": put together by hand (tests, tools)
  EqualArea,   // "equal-area": icobrdf/mesh/tessellation.hpp
  Geodesic,    // "geodesic": icobrdf/mesh/tessellation.hpp
  PolarGauss,  // "polar-gauss": icobrdf/core/grid/reference_grids.hpp
  LatLong,     // "lat-long": icobrdf/core/grid/reference_grids.hpp
};
const char* to_string(GridKind kind);
// The kind whose to_string is `name`; ArgumentError naming the accepted names otherwise.
GridKind parse_grid_kind(const std::string& name);

struct Grid {
  GridKind kind = GridKind::Custom;
  int level = 0;
  RowMatrix3d directions;
  Eigen::VectorXd solid_angles;
  std::vector<std::int64_t> cubature_offsets;
  RowMatrix3d cubature_points;
  Eigen::VectorXd cubature_weights;
  int cubature_degree = 0;  // exactness degree of the cubature, in the cell's own parameter plane
  RowMatrix3d vertices;
  RowMatrix3i faces;
  RowMatrix3i neighbours;
  std::vector<std::uint8_t> is_half;
  Eigen::VectorXi rotate_pi;
  Eigen::VectorXi mirror_xz;
  Eigen::VectorXi mirror_yz;

  int cells() const { return static_cast<int>(solid_angles.size()); }
};

// The same cells with a one-point cubature at each cell's representative direction (weight = its solid
// angle, cubature_degree 1). Used for "centre sampling": a LUT sampled at cell directions and a basis B
// sampled at the same points are consistent, so a BRDF in the span of the basis is recovered exactly.
Grid with_centre_cubature(const Grid& grid);

// The cells `perm` of `g` in that order (new cell k = old cell perm[k]; any list, repeats allowed; ArgumentError
// for a cell outside g): kind,
// level, directions, solid angles and cubature, the fields LUT sampling and the basis read. The mesh and
// the symmetry maps are not carried (they refer to the old numbering).
Grid cells_in_order(const Grid& g, const std::vector<int>& perm);

// Checks the invariants listed above (sizes, unit vectors, z >= 0, weights summing to solid angles within
// a relative 1e-12, permutations being permutations). Throws std::invalid_argument naming the first
// violation.
void validate(const Grid& grid);

}  // namespace icobrdf
