#pragma once
// Makes a grid's cubature equivariant under its symmetry maps (icobrdf/core/grid/grid.hpp: rotate_pi, mirror_xz,
// mirror_yz, which with the identity form a group of order 4).
//
// A per-cell triangle rule is not itself symmetric, so the rule of a cell's mirror partner is in general
// not the mirror image of the cell's rule; the cell averages B of K_n^l then satisfy the symmetry relations
// (B_{rotate_pi(c)} = (-1)^l B_c, ...) only to the rule's accuracy. After this call they hold to rounding:
// for each orbit of cells one representative keeps its rule, averaged over the symmetries that fix it
// (the union of its images, weights divided by their number), and every other cell of the orbit receives
// the image of that rule. Each cell's rule keeps its degree of exactness and its weights still sum to the
// cell's solid angle; cells fixed by a mirror get twice the points. Representative directions are mapped the
// same way. Requires the three maps (ArgumentError otherwise).
#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf {

void make_cubature_equivariant(Grid& grid);

}  // namespace icobrdf
