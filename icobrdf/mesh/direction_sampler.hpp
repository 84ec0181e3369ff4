#pragma once
// DirectionSampler: directions drawn from a density that is constant on each cell of the equal-area
// hemi-icosahedral grid (icobrdf/mesh/tessellation.hpp), and that density evaluated at any direction.
//
// A CellDistribution holds probabilities p_k = m_k / sum_j m_j from non-negative cell masses m_k (for a
// BRDF: the integral of f cos over cell k, or its one-point estimate; icobrdf/io/material_sampler.hpp).
// The density on the hemisphere is piecewise constant:
//   pdf(w) = p_k / A_k   for w in cell k,  A_k = the cell's exact solid angle [sr] (4 pi / (20 4^L) for
//                        whole cells, half of that for the 2^(L+1) cells cut by the equator),
// so it integrates to sum_k p_k = 1 over the hemisphere (per steradian, plain solid-angle measure).
//
// sample(u1, u2), u1, u2 uniform in [0, 1):
//   1. the cell k with cdf_k <= u1 < cdf_{k+1} (binary search; cells with p_k = 0 are never drawn), and
//      u1 rescaled to (u1 - cdf_k) / p_k, again uniform in [0, 1) and independent of k;
//   2. a point uniform in the planar preimage of cell k: the cell is a planar triangle T (a lattice
//      triangle, or for an equator cell the upper half of one, HemiLattice::polygon) of its face's planar
//      Snyder face; with s = sqrt(u1'), the barycentric weights (1 - s, s (1 - u2), s u2) of T's corners
//      are uniform on T;
//   3. the point's image under the inverse Snyder projection of the face.
// Why step 3 is uniform in solid angle: the Snyder map is equal-area on each of the face's 6 right
// sub-triangles with the same constant (planar area = solid angle, the planar face having area 4 pi / 20),
// and continuous across their boundaries (icobrdf/mesh/snyder_projection.hpp). Its Jacobian determinant
// is therefore 1 almost everywhere on the face, also inside cells that straddle a sub-triangle boundary
// (where the map is only piecewise smooth): the image of any planar region of area a has solid angle a,
// and a density uniform in the preimage is uniform, 1 / A_k, in solid angle. tests/mesh/
// test_direction_sampler.cpp checks the Jacobian by finite differences and the images' uniformity.
//
// pdf(w): the cell of w by CellLocator (points on a cell boundary get one adjacent cell, deterministically),
// then p_k / A_k; 0 for w below the horizon (z < -kHorizonSlack).
//
// Accuracy limits: the rescaled u1 carries log2(1 / p_k) fewer bits than u1 (52 - 40 = 12 bits left for a
// cell with p_k = 1e-12); directions are unit vectors to a few ulps, clamped to z >= 0 for equator cells.
// The density is what the masses make it: it does not follow the target inside a cell (see
// icobrdf/io/material_sampler.hpp for what that costs a BRDF's weights).
#include <Eigen/Core>

#include <array>
#include <string>
#include <vector>

#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/mesh/cell_locator.hpp"
#include "icobrdf/mesh/snyder_projection.hpp"

namespace icobrdf {

// Probabilities over cells and their cumulative sums.
class CellDistribution {
 public:
  CellDistribution() = default;
  // mass: one value per cell, finite and >= 0, not all 0; otherwise ArgumentError naming `what` and the
  // first offending cell (or that every mass is 0).
  CellDistribution(const Eigen::VectorXd& mass, const std::string& what);

  int cells() const { return static_cast<int>(p_.size()); }
  double probability(int cell) const { return p_[cell]; }
  const Eigen::VectorXd& probabilities() const { return p_; }
  // The cell drawn by u in [0, 1) (values outside are clamped) and u rescaled within it to [0, 1).
  int sample(double u, double& u_rescaled) const;

 private:
  Eigen::VectorXd p_;
  std::vector<double> cdf_;  // cells + 1 entries, cdf_[0] = 0, cdf_[cells] = 1
};

struct DirectionSample {
  Eigen::Vector3d direction;  // unit vector, z >= 0
  double pdf = 0;             // [1/sr]
  int cell = -1;
};

class DirectionSampler {
 public:
  // The equal-area grid of `level` (0..8, ArgumentError otherwise), with the degree-kLutSamplingDegree
  // cubature of build_fitting_grid (for callers that average a target over cells).
  explicit DirectionSampler(int level);

  int level() const { return grid_.level; }
  int cells() const { return grid_.cells(); }
  const Grid& grid() const { return grid_; }
  const CellLocator& locator() const { return locator_; }

  // A direction uniform in solid angle inside `cell` from u1, u2 in [0, 1) (steps 2 and 3 above).
  Eigen::Vector3d uniform_in_cell(int cell, double u1, double u2) const;

  // Steps 1-3 above; dist must have cells() cells (ArgumentError otherwise).
  DirectionSample sample(const CellDistribution& dist, double u1, double u2) const;
  // p_k / A_k at unit direction w (0 below the horizon; ArgumentError for a non-unit w).
  double pdf(const CellDistribution& dist, const Eigen::Vector3d& w) const;
  // The same at each row of w (n x 3), with CellLocator's batch lookup: the same values, faster.
  Eigen::VectorXd pdf(const CellDistribution& dist, const RowMatrix3d& w) const;

 private:
  void check(const CellDistribution& dist) const;
  Grid grid_;
  CellLocator locator_;
  std::vector<SnyderProjection> faces_;            // the 12 hemi-icosahedron faces
  std::vector<int> face_of_;                       // per cell
  std::vector<std::array<Eigen::Vector3d, 3>> corners_;  // per cell: barycentric corners of its planar triangle
};

}  // namespace icobrdf
