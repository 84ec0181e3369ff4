#pragma once
// The hemisphere basis K sampled on a tessellation: the matrices the discrete engine is made of.
//
// Shapes (C = cells, M = (N+1)(N+2)/2 modes, ANSI order):
//   B  C x M   B_cj = (1/Omega_c) sum_q w_q K_j(x_q): the average of K_j over cell c, by the cell's cubature
//   W  C       solid angles Omega_c [sr] (the diagonal of the weight matrix)
//   G  M x M   Gram matrix B^T W B; equals I for the continuous basis, so max|G - I| measures how well the
//              grid resolves order N (averaging over a cell attenuates high orders)
// The conditioning of G decides whether projection P = W B G^-1 is trustworthy: `check_supported` refuses
// a request whose Gram error exceeds the tolerance, naming the largest order the grid supports.
#include <Eigen/Core>

#include <vector>

#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf {

// Gram error tolerated by default: cell averages of order-N functions must keep their norms to within 10%
// (max |G - I| <= 0.1, so G's eigenvalues lie in [0.9, 1.1] up to off-diagonal mixing). Beyond that, B
// stops representing order N faithfully and the least-squares projection amplifies what the cells cannot see.
inline constexpr double kDefaultGramTolerance = 0.1;

struct DiscreteBasis {
  int order = 0;
  Eigen::MatrixXd B;        // cells x modes
  Eigen::VectorXd W;        // cells
  Eigen::MatrixXd G;        // modes x modes
  double gram_error = 0.0;  // max |G - I|
  double condition = 1.0;   // lambda_max(G) / lambda_min(G)  (G is symmetric positive semi-definite)
  int evaluated_cells = 0;  // cells whose cubature was evaluated: cells(), or one per D2 orbit (see below)
  // A basis split by rows over processes (icobrdf/core/projection/row_split_projection.hpp): B and W hold this process's
  // cells only, G is the sum over all of them, and grid_cells is the grid's count (0: B holds every cell).
  int grid_cells = 0;

  int cells() const { return grid_cells > 0 ? grid_cells : static_cast<int>(B.rows()); }
  int modes() const { return static_cast<int>(B.cols()); }
};

// The Gram matrix G = B^T W B is summed as this many partial products over blocks of cells, added in block
// order (the same bits for any thread count); they are alive together, kGramPartialSums M^2 doubles
// (icobrdf/pipeline/resource_estimate.hpp counts them).
inline constexpr int kGramPartialSums = 16;

// Cell-averaged sampling of K_j, j < M, with the grid's cubature. Threads over cells; the result does not
// depend on the number of threads.
// On a grid with the D2 maps (icobrdf/core/basis/grid_symmetry.hpp) whose cubature is equivariant (each cell's image
// under a map carries the mapped points, in any order, with their weights and its solid angle, within
// kMirroredCubatureRelTol: cubature_is_image, icobrdf/core/basis/grid_symmetry.hpp), only one cell per orbit is evaluated: the other rows are its row times the mode signs, and G = d2_average of the
// representatives' sum, whose blocks within the four symmetry classes are all that is computed (a quarter
// of the cells, a quarter of the Gram work). Cells fixed by a map must then have zero average for the modes
// it reverses (within 1e-12 of max|B|), else, as for any other grid, every cell is evaluated.
DiscreteBasis build_discrete_basis(const Grid& grid, int order);

// The rows of B for the listed cells only, in that order (each the cell average build_discrete_basis
// evaluates; the D2 shortcut is not taken). Threads over cells. ArgumentError for a cell outside the grid.
Eigen::MatrixXd basis_rows(const Grid& grid, int order, const std::vector<int>& cells);

// Sets gram_error and condition from basis.G (the figures build_discrete_basis computes), e.g. after G
// was summed over the processes of a row split.
void set_gram_figures(DiscreteBasis& basis);

// Throws UnsupportedError when basis.gram_error > tolerance or G is singular, with the measured Gram error,
// the condition number and the largest supported order (found by the Gram errors of the leading blocks:
// the basis of order n < N is the leading (n+1)(n+2)/2 block of G).
void check_supported(const DiscreteBasis& basis, double tolerance = kDefaultGramTolerance);

// The largest order n <= basis.order whose leading Gram block has max|G - I| <= tolerance (-1 if none).
int largest_supported_order(const DiscreteBasis& basis, double tolerance = kDefaultGramTolerance);

}  // namespace icobrdf
