#include "icobrdf/core/projection/projection.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <string>
#include <vector>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/projection/projection_tile.hpp"

namespace icobrdf {
namespace {

// LUT columns per block of project_lut (kProjectBlockColumns): enough blocks to balance two or more threads at
// level 4 and up, wide enough that the small second product T P_J of each block costs little.
constexpr Eigen::Index kProjectColumns = kProjectBlockColumns;

}  // namespace


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

Eigen::MatrixXd project_lut(const ProjectionOperator& proj, const Eigen::MatrixXd& lut, LutSymmetry symmetry) {
  if (lut.rows() != proj.P.rows() || lut.cols() != proj.P.rows())
    throw ArgumentError("project: LUT is " + std::to_string(lut.rows()) + " x " + std::to_string(lut.cols()) +
                        ", expected " + std::to_string(proj.P.rows()) + " x " + std::to_string(proj.P.rows()) + " (cells x cells)");
  // C = sum_J (P^T F_J) P_J over fixed blocks J of kProjectColumns LUT columns. Threads take whole blocks
  // and each block's products run single-threaded, so the result does not depend on the thread count
  // (partials are added in block order). Eigen's own threading of one (modes x cells) * (cells x cells)
  // product splits the few result rows between threads in multiples of its 12-row kernel (12 + 33 rows for
  // 45 modes on 2 threads), which left one core idle most of the time; splitting the columns balances it.
  const Eigen::Index cells = lut.rows(), modes = proj.P.cols();
  const Eigen::Index blocks = (cells + kProjectColumns - 1) / kProjectColumns;
  std::vector<Eigen::MatrixXd> partial(static_cast<size_t>(blocks));
  const PackedProjection packed = pack_projection(proj.P);  // once, shared by the threads
#pragma omp parallel
  {
    Eigen::MatrixXd t(modes, kProjectColumns), below(modes, kProjectColumns);  // P^T F_J, per thread
    std::vector<double> acc;
#pragma omp for schedule(dynamic)
    for (Eigen::Index b = 0; b < blocks; ++b) {
      const Eigen::Index c0 = b * kProjectColumns, w = std::min(kProjectColumns, cells - c0);
      const double* fj = lut.data() + c0 * cells;
      Eigen::MatrixXd& part = partial[static_cast<size_t>(b)];
      if (symmetry == LutSymmetry::General) {
        projection_tile(packed, proj.P, fj, cells, w, t, acc);  // P^T F_J at the CPU's vector width
        part.noalias() = t * proj.P.middleRows(c0, w);
      } else {
        projection_tile(packed, proj.P, fj, cells, w, t, acc, c0, c0 + w);        // the diagonal block
        if (c0 + w < cells)
          projection_tile(packed, proj.P, fj, cells, w, below, acc, c0 + w, cells);  // the rows below it
        else
          below.setZero(modes, w);
        part.noalias() = below * proj.P.middleRows(c0, w);
        part = part + part.transpose().eval();
        part.noalias() += t * proj.P.middleRows(c0, w);
      }
    }
  }
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(modes, modes);
  for (const auto& p : partial) c += p;
  return c;
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
