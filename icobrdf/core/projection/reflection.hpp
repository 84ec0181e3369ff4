#pragma once
// The reflection operator of a LUT and its white-furnace figures.
//
// Radiance is given per cell (cells-vector, W/(m^2 sr)); D = cell-mean cosines (icobrdf/core/projection/lut.hpp), Omega = solid angles.
//   f LUT:  L_o(r) = sum_i F_ir D_i Omega_i L_i(i)      (L_o = F^T diag(D Omega) L_i)
//   g LUT:  L_o(r) = sum_i G_ir Omega_i L_i(i)
// Directional albedo of incident cell i: a_i = sum_r f_ir D_r Omega_r (= integral f cos theta_r dOmega_r);
// for a g LUT f_ir = G_ir / D_i. Energy conservation (white furnace): a_i <= 1 for every i.
#include <Eigen/Core>

#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/core/projection/lut.hpp"

namespace icobrdf {

Eigen::VectorXd reflect_radiance(const Eigen::MatrixXd& lut, bool cosine, const Grid& grid, const Eigen::VectorXd& incident);
Eigen::VectorXd directional_albedo(const Eigen::MatrixXd& lut, bool cosine, const Grid& grid);

struct WhiteFurnace {
  double max_albedo = 0.0;
  int worst_cell = -1;
  double mean_albedo = 0.0;  // solid-angle weighted mean over incident cells
};
WhiteFurnace white_furnace(const Eigen::MatrixXd& lut, bool cosine, const Grid& grid);

}  // namespace icobrdf
