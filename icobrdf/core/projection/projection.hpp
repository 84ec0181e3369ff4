#pragma once
// Projection, reconstruction and smoothing of lookup tables as matrix products.
//
// With B (cells x modes), W (cell solid angles) and G = B^T W B from icobrdf/core/projection/discrete_basis.hpp:
//   least squares   P = W B G^-1     (cells x modes) exact for LUTs in the span: P^T (B C B^T) P = C
//   plain           P = W B          (the direct discretization of the projection integral)
//   spectrum        C = P^T F P      (modes x modes) for a LUT F (cells x cells, rows = incident cells)
//   reconstruction  F' = B C B^T
//   smoothing       S F S^T with S = B diag(w) P^T, w the low-pass mode weights; S is never formed:
//                   S F S^T = B (w w^T o (P^T F P)) B^T.
// The continuous analogue of P^T F P is C_ab = integral integral F K_a K_b; with equal-area cells the
// discrete operator commutes with the cell symmetries (rotation by pi, mirrors) exactly.
#include <Eigen/Core>

#include "icobrdf/core/projection/discrete_basis.hpp"
#include "icobrdf/core/basis/lowpass_filter.hpp"

namespace icobrdf {

struct ProjectionOperator {
  enum class Kind { LeastSquares, Plain };
  Kind kind = Kind::LeastSquares;
  Eigen::MatrixXd P;  // cells x modes
};

// LeastSquares requires G positive definite (UnsupportedError otherwise, with the condition number).
ProjectionOperator make_projection(const DiscreteBasis& basis, ProjectionOperator::Kind kind = ProjectionOperator::Kind::LeastSquares);

// What the caller knows of F's symmetry. Symmetric: F = F^T (the f-form LUT of a reciprocal BRDF, rows and
// columns on the same cells); project_lut then reads only F(k, j) with k >= kProjectBlockColumns x
// floor(j / kProjectBlockColumns), about half of F, and does about half the flops: with F's column blocks J,
// C = sum_J (A_J + A_J^T + D_J), A_J = P(below J)^T F(below J, J) P_J, D_J = P_J^T F(J, J) P_J. Nothing checks
// the claim (a check would read all of F); an F that is not symmetric gives the projection of its lower part
// mirrored.
enum class LutSymmetry { General, Symmetric };
constexpr Eigen::Index kProjectBlockColumns = 512;  // LUT columns per block of project_lut

Eigen::MatrixXd project_lut(const ProjectionOperator& proj, const Eigen::MatrixXd& lut,
                            LutSymmetry symmetry = LutSymmetry::General);                          // P^T F P
Eigen::MatrixXd reconstruct_lut(const DiscreteBasis& basis, const Eigen::MatrixXd& coefficients);  // B C B^T
Eigen::MatrixXd smooth_lut(const DiscreteBasis& basis, const ProjectionOperator& proj, const Eigen::MatrixXd& lut,
                           const LowPassFilter& filter);                                           // S F S^T

// Applies the filter to a coefficient matrix: C_ab w_n(a) w_n(b).
Eigen::MatrixXd filter_coefficients(const Eigen::MatrixXd& coefficients, int order, const LowPassFilter& filter);

}  // namespace icobrdf
