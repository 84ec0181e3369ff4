#include "core/discrete_basis.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "core/hemisphere_basis.hpp"

namespace icobrdf {

DiscreteBasis build_discrete_basis(const Grid& grid, int order) {
  if (order < 0) throw ArgumentError("discrete basis: order expected >= 0, got " + std::to_string(order));
  const int cells = grid.cells();
  const int modes = hemisphere_basis_count(order);
  DiscreteBasis d;
  d.order = order;
  d.W = grid.solid_angles;
  d.B.setZero(cells, modes);
#pragma omp parallel
  {
    std::vector<double> k(static_cast<size_t>(modes));
#pragma omp for schedule(static)
    for (int c = 0; c < cells; ++c) {
      const auto b = grid.cubature_offsets[static_cast<size_t>(c)], e = grid.cubature_offsets[static_cast<size_t>(c) + 1];
      Eigen::VectorXd acc = Eigen::VectorXd::Zero(modes);
      for (auto q = b; q < e; ++q) {
        hemisphere_basis_eval(order, grid.cubature_points.row(q).transpose(), k.data());
        acc += grid.cubature_weights[q] * Eigen::Map<const Eigen::VectorXd>(k.data(), modes);
      }
      d.B.row(c) = acc.transpose() / grid.solid_angles[c];
    }
  }
  d.G = d.B.transpose() * d.W.asDiagonal() * d.B;
  d.gram_error = (d.G - Eigen::MatrixXd::Identity(modes, modes)).cwiseAbs().maxCoeff();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(d.G, Eigen::EigenvaluesOnly);
  const double lo = eig.eigenvalues().minCoeff(), hi = eig.eigenvalues().maxCoeff();
  d.condition = lo > 0.0 ? hi / lo : std::numeric_limits<double>::infinity();
  return d;
}

int largest_supported_order(const DiscreteBasis& basis, double tolerance) {
  int best = -1;
  for (int n = 0; n <= basis.order; ++n) {
    const int m = hemisphere_basis_count(n);
    const double err = (basis.G.topLeftCorner(m, m) - Eigen::MatrixXd::Identity(m, m)).cwiseAbs().maxCoeff();
    if (err > tolerance) break;
    best = n;
  }
  return best;
}

void check_supported(const DiscreteBasis& basis, double tolerance) {
  if (basis.gram_error <= tolerance && std::isfinite(basis.condition)) return;
  const int best = largest_supported_order(basis, tolerance);
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "order %d exceeds what a grid of %d cells resolves: Gram error max|G - I| = %.3g > tolerance %.3g "
                "(condition number %.3g); largest supported order is %d",
                basis.order, basis.cells(), basis.gram_error, tolerance, basis.condition, best);
  throw UnsupportedError(buf);
}

}  // namespace icobrdf
