#pragma once
// Hemi-icosahedral tessellations of the upper hemisphere, handed to core as a Grid (icobrdf/core/grid/grid.hpp).
//
// build_equal_area_grid(L): kind "equal-area". The icosahedron (icobrdf/mesh/icosahedron.hpp: 2-fold axis along
// +z, z = 0 a mirror plane) restricted to z >= 0 is 8 whole faces and 4 faces halved along a median.
// Each face carries the aperture-4 lattice of level L (n = 2^L) placed on the sphere by Snyder's
// equal-area projection (icobrdf/mesh/snyder_projection.hpp). Cells (HemiLattice numbering, shared with
// CellLocator): 10 4^L + 2^(L+1); every whole cell subtends exactly 4 pi / (20 4^L) sr, each half cell
// exactly half of that; solid_angles hold these exact values.
//
// build_geodesic_grid(L): kind "geodesic", the same cells placed by the gnomonic projection (geodesic
// triangles, not equal-area); solid_angles are the exact spherical-triangle areas (Van Oosterom-Strackee).
//
// Grid fields:
//   directions   image on the sphere of the planar centroid of each cell (for half cells, of the half
//                triangle), so it lies inside the cell.
//   cubature     per cell the Stroud conical product rule (icobrdf/mesh/triangle_rule.hpp) of the requested degree
//                applied in the planar face coordinates. Equal-area: the projection is area-preserving and
//                piecewise smooth, so the planar cell is first cut along the face's 3 medians (the 6
//                sub-triangle boundaries, where the map has kinks) and the rule applied per piece; the
//                weights are the planar weights (no Jacobian) and sum exactly to the cell's solid angle.
//                cubature_degree = d: for every cell, the rule integrates exactly every integrand that is a
//                polynomial of total degree <= d in the planar coordinates on each piece.
//                The rules are then made equivariant under the three symmetry maps
//                (icobrdf/mesh/cubature_symmetry.hpp): the rule of a cell's partner is the exact image of the cell's
//                rule, so symmetry relations of cell averages hold to rounding.
//                Geodesic: weights are planar weights times the gnomonic Jacobian h / |p|^3, then rescaled
//                so that each cell's weights sum to its exact solid angle; cubature_degree = d refers to
//                the integrand times the Jacobian being a polynomial of degree <= d in the flat face.
//   vertices, faces (counter-clockwise from outside), neighbours (-1 across the equator), is_half from
//                the OpenMesh mesh (icobrdf/mesh/tessellation_mesh.hpp).
//   rotate_pi (x,y,z) -> (-x,-y,z), mirror_xz (y -> -y), mirror_yz (x -> -x): the cell containing the image
//                of each cell (the tessellation is invariant under all three, cell for cell).
//
// Pieces having the face centre as a corner (the 6 pieces of the central cell of each face) are
// integrated with the rule's collapsed corner on the centre (a Duffy transform): the map is smooth in polar
// coordinates around the centre but has singular Cartesian derivatives there.
//
// Default cubature degree kDefaultCubatureDegree = 9: 25 points per piece (one piece for most cells, 2
// for cells cut by a face median, 6 for the central cell of a face; 27.2 points per cell on average at
// level 5). At level 5 it gives cell averages of the hemisphere basis K_n^l (|K| <= 3.3; Zernike polynomials
// pulled back by the Lambert map) up to order n = 32 with a maximum error of 1.6e-6 (in the equator cells,
// where K_32 varies on the scale z ~ 0.006) and an RMS error of 3.3e-8 over all cells (degree 7: max
// 1.9e-5; tests/mesh/test_cubature.cpp). Pass a higher degree for more (degree 13: 49 points per piece).
#include <string>

#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf {

inline constexpr int kDefaultCubatureDegree = 9;
inline constexpr int kMaxTessellationLevel = 8;

// 0 <= level <= 8, 1 <= cubature_degree <= 61 (ArgumentError otherwise).
Grid build_equal_area_grid(int level);
Grid build_equal_area_grid(int level, int cubature_degree);
Grid build_geodesic_grid(int level);
Grid build_geodesic_grid(int level, int cubature_degree);
// kind: "equal-area" or "geodesic".
Grid build_hemi_icosahedral_grid(int level, GridKind kind, int cubature_degree = kDefaultCubatureDegree);
// The same with the kind by name (parse_grid_kind; ArgumentError for any kind but these two).
Grid build_hemi_icosahedral_grid(int level, const std::string& kind, int cubature_degree = kDefaultCubatureDegree);

// Cubature degree of the rule that cell-averages LUT rows during fits: each LUT entry costs
// (points per cell)^2 model evaluations, so fits use a cheap rule.
inline constexpr int kLutSamplingDegree = 2;

// The grid a fit samples on, LUT rows and basis B alike (so a BRDF in the span of the basis is recovered
// exactly): one point per cell at its direction when `centre`, else the degree-kLutSamplingDegree rule.
Grid build_fitting_grid(int level, GridKind kind, bool centre);
Grid build_fitting_grid(int level, const std::string& kind, bool centre);  // kind by name, as above

}  // namespace icobrdf
