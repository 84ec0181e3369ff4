#include "icobrdf/core/projection/direct_projection.hpp"

#include <algorithm>
#include <string>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"

namespace icobrdf {
namespace {

// Incident points per block: each block owns one partial M x M sum per channel, added in block order.
constexpr Eigen::Index kBlockPoints = 32;

}  // namespace

std::vector<Eigen::MatrixXd> direct_projection(const BrdfModel& model, const Grid& grid, int order, bool cosine,
                                               DirectModes modes) {
  if (!model.delta_parts().empty())
    throw ArgumentError("direct quadrature of '" + quoted_text(model.spec()) + "': delta parts have no pointwise values");
  const int m = hemisphere_basis_count(order);  // validates the order
  const int ch = model.channels();
  const Eigen::Index q_total = grid.cubature_points.rows();
  if (q_total == 0 || grid.cubature_weights.size() != q_total)
    throw ArgumentError("direct quadrature: grid has " + std::to_string(q_total) + " cubature points and " +
                        std::to_string(grid.cubature_weights.size()) + " weights");
  Eigen::MatrixXd table;  // Q x M, only for DirectModes::Cached
  if (modes == DirectModes::Cached) table = hemisphere_basis_matrix(order, grid.cubature_points);
  const Eigen::Index blocks = (q_total + kBlockPoints - 1) / kBlockPoints;
  std::vector<std::vector<Eigen::MatrixXd>> partial(static_cast<size_t>(blocks));
#pragma omp parallel
  {
    Eigen::MatrixXd f(q_total, ch);
    RowMatrix3d wi(q_total, 3);
    Eigen::VectorXd ki(m), kr(m);
    Eigen::MatrixXd t(m, ch);
#pragma omp for schedule(dynamic)
    for (Eigen::Index b = 0; b < blocks; ++b) {
      auto& acc = partial[static_cast<size_t>(b)];
      acc.assign(static_cast<size_t>(ch), Eigen::MatrixXd::Zero(m, m));
      const Eigen::Index q0 = b * kBlockPoints, q1 = std::min(q_total, q0 + kBlockPoints);
      for (Eigen::Index q = q0; q < q1; ++q) {
        wi.rowwise() = grid.cubature_points.row(q);
        model.eval(wi, grid.cubature_points, f);
        // t_b = sum_q' w_q' f(x_q, x_q') K_b(x_q')
        if (modes == DirectModes::Cached) {
          t.noalias() = table.transpose() * (grid.cubature_weights.asDiagonal() * f);
        } else {
          t.setZero();
          for (Eigen::Index r = 0; r < q_total; ++r) {
            hemisphere_basis_eval(order, grid.cubature_points.row(r).transpose(), kr.data());
            for (int c = 0; c < ch; ++c) t.col(c) += (grid.cubature_weights[r] * f(r, c)) * kr;
          }
        }
        if (modes == DirectModes::Cached)
          ki = table.row(q).transpose();
        else
          hemisphere_basis_eval(order, grid.cubature_points.row(q).transpose(), ki.data());
        const double wq = grid.cubature_weights[q] * (cosine ? grid.cubature_points(q, 2) : 1.0);
        for (int c = 0; c < ch; ++c) acc[static_cast<size_t>(c)].noalias() += (wq * ki) * t.col(c).transpose();
      }
    }
  }
  std::vector<Eigen::MatrixXd> out(static_cast<size_t>(ch), Eigen::MatrixXd::Zero(m, m));
  for (const auto& acc : partial)
    for (int c = 0; c < ch; ++c) out[static_cast<size_t>(c)] += acc[static_cast<size_t>(c)];
  return out;
}

}  // namespace icobrdf
