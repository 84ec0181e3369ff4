// Build a grid and run the LUT operators: sample a LUT, project it (C = P^T F P), reconstruct it
// (B C B^T) and smooth it (S F S^T), and check the white furnace of a Lambertian surface.
//   lut_operators
#include <cmath>
#include <cstdio>
#include <memory>

#include "icobrdf/core/projection/discrete_basis.hpp"
#include "icobrdf/core/projection/lut.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/projection/projection.hpp"
#include "icobrdf/core/projection/reflection.hpp"
#include "icobrdf/mesh/tessellation.hpp"

int main() {
  using namespace icobrdf;
  const Grid grid = build_equal_area_grid(3);                  // 656 equal-area cells
  const auto model = parse_model_source("model:lambert:albedo=0.5");
  const Lut lut = build_lut(*model, grid, false, LutSampling::CellCentre);  // cells x cells per channel, f = 0.5 / pi
  const DiscreteBasis basis = build_discrete_basis(grid, 4);   // B: cells x 15, G = B^T W B ~ I
  check_supported(basis);                                      // throws when the grid cannot resolve order 4
  const ProjectionOperator p = make_projection(basis);         // P = W B G^-1
  const Eigen::MatrixXd c = project_lut(p, lut.channels[0]);   // 15 x 15; C_00 = 2 x albedo for Lambert
  const Eigen::MatrixXd back = reconstruct_lut(basis, c);
  const Eigen::MatrixXd smooth = smooth_lut(basis, p, lut.channels[0], LowPassFilter{});
  const auto wf = white_furnace(lut.channels[0], false, grid);  // directional albedo per incident cell
  std::printf("%d cells, Gram error %.2e, C_00 = %.6f (2 x albedo = 1), max |B C B^T - F| = %.2e, max |S F S^T - F| = %.2e\n",
              grid.cells(), basis.gram_error, c(0, 0), (back - lut.channels[0]).cwiseAbs().maxCoeff(),
              (smooth - lut.channels[0]).cwiseAbs().maxCoeff());
  std::printf("white furnace: max directional albedo %.6f (albedo 0.5)\n", wf.max_albedo);
  // A constant is reproduced to the rounding of sums over 656 cells; 1e-6 leaves orders of magnitude of room.
  constexpr double kConstantTolerance = 1e-6;
  return std::abs(c(0, 0) - 1.0) < kConstantTolerance && std::abs(wf.max_albedo - 0.5) < kConstantTolerance ? 0 : 1;
}
