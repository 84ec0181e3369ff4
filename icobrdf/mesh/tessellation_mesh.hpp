#pragma once
// The hemi-icosahedral tessellation as an OpenMesh triangle mesh (one mesh face per cell).
//
// Faces are added in cell order (face handle index = cell id of HemiLattice), counter-clockwise seen
// from outside; half cells are triangles (the upper half of a lattice triangle cut along its median).
// Vertices shared across lattice and icosahedron edges are welded exactly by integer lattice keys
// (icosahedron vertex id, edge + integer position, or face + integer barycentrics), never by rounding.
// The mesh is a topological disk whose boundary is the equator.
//
// Vertex positions: "equal-area" places lattice points with the inverse Snyder projection
// (icobrdf/mesh/snyder_projection.hpp), "geodesic" with the gnomonic projection (icobrdf/mesh/gnomonic_projection.hpp);
// icosahedron corners are the exact normalized vertices.
//
// Per-face properties: cell_id, ico_face (hemi-icosahedron face 0..11), solid_angle [sr] (exact:
// 4 pi / (20 4^L) or half of it for equal-area; Van Oosterom-Strackee for geodesic), half (cut by the
// equator).
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <memory>
#include <string>

#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf {

class HemiLattice;

struct TessellationTraits : public OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
};
using TessellationTriMesh = OpenMesh::TriMesh_ArrayKernelT<TessellationTraits>;

struct TessellationMesh {
  std::string kind;
  int level = 0;
  TessellationTriMesh mesh;
  OpenMesh::FPropHandleT<int> cell_id;
  OpenMesh::FPropHandleT<int> ico_face;
  OpenMesh::FPropHandleT<double> solid_angle;
  OpenMesh::FPropHandleT<bool> half;
};

// kind: "equal-area" or "geodesic"; 0 <= level <= 8 (ArgumentError otherwise).
std::unique_ptr<TessellationMesh> build_tessellation_mesh(int level, const std::string& kind = "equal-area");
std::unique_ptr<TessellationMesh> build_tessellation_mesh(const HemiLattice& lattice, const std::string& kind);
// kind by name: GridKind::EqualArea or GridKind::Geodesic; ArgumentError("unknown grid kind ...") for any
// other name (the tessellations exist in these two placements only).
GridKind hemi_icosahedral_kind(const std::string& kind);

}  // namespace icobrdf
