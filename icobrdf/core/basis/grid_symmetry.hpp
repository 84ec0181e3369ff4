#pragma once
// The D2 symmetry of a hemisphere grid seen from the K basis, used to skip work that symmetry determines.
//
// D2 = {identity, rotation by pi about the normal, mirror y -> -y, mirror x -> -x}; a grid carries it when
// its symmetry maps (icobrdf/core/grid/grid.hpp: rotate_pi, mirror_xz, mirror_yz) are present. Under each map the
// basis functions only change sign (paper eq. 5 with phi -> phi + pi, -phi, pi - phi):
//   rotation  (-1)^l;   mirror y -> -y  +1 for l >= 0, -1 for l < 0;   mirror x -> -x  their product.
// The pair (l odd, l < 0) fixes all three signs: the mode's symmetry class (0..3). A D2-invariant
// quantity such as G = B^T W B, or the C of an isotropic BRDF, couples only modes of the same class, and
// it equals sum_s D_s X D_s (D_s the diagonal of signs) for X summed over one cell per orbit divided by
// the size of that cell's stabilizer: 4 X_ab within a class, 0 across classes (d2_average).
#include <Eigen/Core>

#include <vector>

#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf {

struct D2Map {
  const Eigen::VectorXi* cells;  // the grid's cell map
  double sx, sy;                 // the direction map (x, y, z) -> (sx x, sy y, z)
  int sign(int l) const;         // sign of K_n^l under it
};

// Symmetry class of ANSI mode j: (|l| odd) + 2 (l < 0).
int d2_class(int j);

// True when the grid has all three maps (each of size cells()).
bool has_d2_maps(const Grid& grid);

// The three non-identity maps of a grid with has_d2_maps.
std::vector<D2Map> d2_maps(const Grid& grid);

// One cell per orbit (the orbit's smallest index), with 1 / |stabilizer| (1, 1/2 or 1/4).
struct D2Representative {
  int cell;
  double weight;
};
std::vector<D2Representative> d2_representatives(const Grid& grid);

// Mirrored cubature: how far the sampling of a cell and of its image under a D2 map may differ, relative
// (points are unit vectors, so for them relative is absolute). A rule built by mapping points
// (icobrdf/mesh/cubature_symmetry.hpp) matches exactly; solid angles and rules computed cell by cell from mirrored
// vertices agree to a few ulps of their construction; 1e-12 leaves room for that and rejects any grid that
// is symmetric only up to its discretization (a point or weight off by 1e-9 already fails).
inline constexpr double kMirroredCubatureRelTol = 1e-12;

// The one rule for "cell t carries the image of cell c's sampling under map s": the same number of points;
// c's points mapped by s are t's points as a set (any order), each with its weight, within
// kMirroredCubatureRelTol; solid angles equal within the same tolerance. The sampling is the cubature, or,
// with `centres`, one point per cell at its direction weighted by its solid angle (centre sampling). The
// cell average of a function over a point set does not depend on the order of the points, so B_t (and a LUT
// row of t) is then sign_s B_c up to rounding. False when t is not a cell of the grid.
bool cubature_is_image(const Grid& grid, const D2Map& s, int c, int t, bool centres = false);

// True when the grid has its D2 maps and every cell's image under every map carries the image of its
// sampling (cubature_is_image).
bool sampling_is_d2_symmetric(const Grid& grid, bool centres = false);

// True when m(image(c), j) = sign_j m(c, j) within tol * max|m| for every map, cell and mode
// (m is cells x modes in ANSI order, e.g. B or P).
bool rows_are_d2_equivariant(const Grid& grid, const Eigen::MatrixXd& m, double tol);

// sum_s D_s X D_s: 4 X_ab for modes of the same class, 0 otherwise (X square, ANSI order).
Eigen::MatrixXd d2_average(const Eigen::MatrixXd& x);

}  // namespace icobrdf
