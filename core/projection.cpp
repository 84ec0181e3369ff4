#include "core/projection.hpp"

#include <Eigen/Cholesky>
#include <string>

#include "core/error.hpp"

namespace icobrdf {

ProjectionOperator make_projection(const DiscreteBasis& basis, ProjectionOperator::Kind kind) {
  ProjectionOperator p;
  p.kind = kind;
  const Eigen::MatrixXd wb = basis.W.asDiagonal() * basis.B;
  if (kind == ProjectionOperator::Kind::Plain) {
    p.P = wb;
    return p;
  }
  Eigen::LLT<Eigen::MatrixXd> llt(basis.G);
  if (llt.info() != Eigen::Success)
    throw UnsupportedError("projection: Gram matrix of order " + std::to_string(basis.order) + " on " +
                           std::to_string(basis.cells()) + " cells is not positive definite (condition number " +
                           std::to_string(basis.condition) + ")");
  // P = W B G^-1  <=>  P^T = G^-1 (W B)^T since G is symmetric.
  p.P = llt.solve(wb.transpose()).transpose();
  return p;
}

Eigen::MatrixXd project_lut(const ProjectionOperator& proj, const Eigen::MatrixXd& lut) {
  if (lut.rows() != proj.P.rows() || lut.cols() != proj.P.rows())
    throw ArgumentError("project: LUT is " + std::to_string(lut.rows()) + " x " + std::to_string(lut.cols()) +
                        ", expected " + std::to_string(proj.P.rows()) + " x " + std::to_string(proj.P.rows()) + " (cells x cells)");
  // (P^T F) P: the large product has the few modes as its rows, a shape Eigen's GEMM runs at ~1.3x the
  // speed of F P (benchmarks/RESULTS.md).
  const Eigen::MatrixXd pf = proj.P.transpose() * lut;  // modes x cells
  return pf * proj.P;
}

Eigen::MatrixXd reconstruct_lut(const DiscreteBasis& basis, const Eigen::MatrixXd& c) {
  if (c.rows() != basis.modes() || c.cols() != basis.modes())
    throw ArgumentError("reconstruct: coefficient matrix is " + std::to_string(c.rows()) + " x " + std::to_string(c.cols()) +
                        ", expected " + std::to_string(basis.modes()) + " x " + std::to_string(basis.modes()));
  const Eigen::MatrixXd bc = basis.B * c;  // cells x modes
  return bc * basis.B.transpose();
}

Eigen::MatrixXd filter_coefficients(const Eigen::MatrixXd& c, int order, const LowPassFilter& filter) {
  const Eigen::VectorXd w = mode_weights(filter, order);
  if (c.rows() != w.size() || c.cols() != w.size())
    throw ArgumentError("filter: coefficient matrix is " + std::to_string(c.rows()) + " x " + std::to_string(c.cols()) +
                        ", expected " + std::to_string(w.size()) + " square for order " + std::to_string(order));
  return w.asDiagonal() * c * w.asDiagonal();
}

Eigen::MatrixXd smooth_lut(const DiscreteBasis& basis, const ProjectionOperator& proj, const Eigen::MatrixXd& lut,
                           const LowPassFilter& filter) {
  return reconstruct_lut(basis, filter_coefficients(project_lut(proj, lut), basis.order, filter));
}

}  // namespace icobrdf
