#pragma once
// Projection, reconstruction and smoothing of lookup tables as matrix products.
//
// With B (cells x modes), W (cell solid angles) and G = B^T W B from core/discrete_basis.hpp:
//   least squares   P = W B G^-1     (cells x modes) exact for LUTs in the span: P^T (B C B^T) P = C
//   plain           P = W B          (the direct discretization of the projection integral)
//   spectrum        C = P^T F P      (modes x modes) for a LUT F (cells x cells, rows = incident cells)
//   reconstruction  F' = B C B^T
//   smoothing       S F S^T with S = B diag(w) P^T, w the low-pass mode weights; S is never formed:
//                   S F S^T = B (w w^T o (P^T F P)) B^T.
// The continuous analogue of P^T F P is C_ab = integral integral F K_a K_b; with equal-area cells the
// discrete operator commutes with the cell symmetries (rotation by pi, mirrors) exactly.
#include <Eigen/Core>

#include "core/discrete_basis.hpp"
#include "core/lowpass_filter.hpp"

namespace icobrdf {

struct ProjectionOperator {
  enum class Kind { LeastSquares, Plain };
  Kind kind = Kind::LeastSquares;
  Eigen::MatrixXd P;  // cells x modes
};

// LeastSquares requires G positive definite (UnsupportedError otherwise, with the condition number).
ProjectionOperator make_projection(const DiscreteBasis& basis, ProjectionOperator::Kind kind = ProjectionOperator::Kind::LeastSquares);

Eigen::MatrixXd project_lut(const ProjectionOperator& proj, const Eigen::MatrixXd& lut);          // P^T F P
Eigen::MatrixXd reconstruct_lut(const DiscreteBasis& basis, const Eigen::MatrixXd& coefficients);  // B C B^T
Eigen::MatrixXd smooth_lut(const DiscreteBasis& basis, const ProjectionOperator& proj, const Eigen::MatrixXd& lut,
                           const LowPassFilter& filter);                                           // S F S^T

// Applies the filter to a coefficient matrix: C_ab w_n(a) w_n(b).
Eigen::MatrixXd filter_coefficients(const Eigen::MatrixXd& coefficients, int order, const LowPassFilter& filter);

}  // namespace icobrdf
