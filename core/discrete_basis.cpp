#include "core/discrete_basis.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>
#include <string>

#include "core/error.hpp"
#include "core/brdf_model.hpp"  // kHorizonSlack: the slack core/lambert_map.cpp accepts below z = 0
#include "core/grid_symmetry.hpp"
#include "core/hemisphere_basis.hpp"

namespace icobrdf {

namespace {

// Cells per block of the Gram product: each block adds (W^1/2 B)_block^T (W^1/2 B)_block; blocks are summed
// in a fixed order so G does not depend on the number of threads.
constexpr int kGramBlocks = 16;
// Off-block entries of G (between modes of different D2 symmetry classes) at most this fraction of
// max|G|: G is then treated as block diagonal for its eigenvalues; by Weyl's inequality this moves each
// eigenvalue by at most the Frobenius norm of the dropped part (<= modes x this x max|G|, ~1e-12 at
// order 32), far below the precision a condition number is read to.
constexpr double kBlockDiagonalTol = 1e-15;
// B counts as D2-equivariant (cell averages on mirrored cells equal up to the signs of the modes) within
// this fraction of max|B|: rounding of the mirrored cubature; an asymmetric rule differs by ~1e-6 or more.
constexpr double kEquivarianceTol = 1e-12;

// Extreme eigenvalues of the symmetric G: per symmetry class when G is block diagonal to kBlockDiagonalTol,
// else of the whole matrix.
std::pair<double, double> extreme_eigenvalues(const Eigen::MatrixXd& g) {
  const int m = static_cast<int>(g.rows());
  std::vector<int> cls(static_cast<size_t>(m));
  for (int j = 0; j < m; ++j) cls[static_cast<size_t>(j)] = d2_class(j);
  const double scale = g.cwiseAbs().maxCoeff();
  bool block_diagonal = true;
  for (int a = 0; a < m && block_diagonal; ++a)
    for (int b = 0; b < m; ++b)
      if (cls[static_cast<size_t>(a)] != cls[static_cast<size_t>(b)] && std::abs(g(a, b)) > kBlockDiagonalTol * scale) {
        block_diagonal = false;
        break;
      }
  if (!block_diagonal) {
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(g, Eigen::EigenvaluesOnly);
    return {eig.eigenvalues().minCoeff(), eig.eigenvalues().maxCoeff()};
  }
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int k = 0; k < 4; ++k) {
    std::vector<int> idx;
    for (int j = 0; j < m; ++j)
      if (cls[static_cast<size_t>(j)] == k) idx.push_back(j);
    if (idx.empty()) continue;
    const int s = static_cast<int>(idx.size());
    Eigen::MatrixXd block(s, s);
    for (int a = 0; a < s; ++a)
      for (int b = 0; b < s; ++b) block(a, b) = g(idx[static_cast<size_t>(a)], idx[static_cast<size_t>(b)]);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(block, Eigen::EigenvaluesOnly);
    lo = std::min(lo, eig.eigenvalues().minCoeff());
    hi = std::max(hi, eig.eigenvalues().maxCoeff());
  }
  return {lo, hi};
}

}  // namespace

DiscreteBasis build_discrete_basis(const Grid& grid, int order) {
  if (order < 0) throw ArgumentError("discrete basis: order expected >= 0, got " + std::to_string(order));
  const int cells = grid.cells();
  const int modes = hemisphere_basis_count(order);
  // Validate up front: nothing may throw inside the parallel loop.
  for (Eigen::Index q = 0; q < grid.cubature_points.rows(); ++q)
    if (!grid.cubature_points.row(q).allFinite() || !(grid.cubature_points(q, 2) >= -kHorizonSlack))
      throw ArgumentError("discrete basis: cubature point " + std::to_string(q) + " is not a finite direction with z >= 0");
  DiscreteBasis d;
  d.order = order;
  d.W = grid.solid_angles;
  d.B.resize(cells, modes);
#pragma omp parallel
  {
    std::vector<double> scratch(static_cast<size_t>(hemisphere_basis_lanes_scratch(order)));
    std::vector<double> acc(static_cast<size_t>(modes * kBasisLanes));
    Eigen::RowVectorXd row(modes);
#pragma omp for schedule(static)
    for (int c = 0; c < cells; ++c) {
      const auto b = grid.cubature_offsets[static_cast<size_t>(c)], e = grid.cubature_offsets[static_cast<size_t>(c) + 1];
      std::fill(acc.begin(), acc.end(), 0.0);
      for (auto q0 = b; q0 < e; q0 += kBasisLanes) {
        alignas(32) double x[kBasisLanes], y[kBasisLanes], z[kBasisLanes], w[kBasisLanes];
        for (int l = 0; l < kBasisLanes; ++l) {
          const auto q = q0 + l;
          const bool in = q < e;  // a short last group is padded with the pole at weight 0
          x[l] = in ? grid.cubature_points(q, 0) : 0.0;
          y[l] = in ? grid.cubature_points(q, 1) : 0.0;
          z[l] = in ? grid.cubature_points(q, 2) : 1.0;
          w[l] = in ? grid.cubature_weights[q] : 0.0;
        }
        hemisphere_basis_eval_lanes(order, x, y, z, w, scratch.data(), acc.data(), true);
      }
      for (int j = 0; j < modes; ++j) {
        const double* a = acc.data() + static_cast<size_t>(j) * kBasisLanes;
        row[j] = ((a[0] + a[1]) + (a[2] + a[3])) / grid.solid_angles[c];
      }
      d.B.row(c) = row;
    }
  }
  // G = B^T W B as a sum of symmetric rank updates over fixed blocks of cells (lower triangle, then
  // mirrored). On a D2-symmetric grid whose B is equivariant (core/grid_symmetry.hpp) only one cell per
  // orbit enters, weighted by 1 / |stabilizer|, and G = d2_average of that sum: a quarter of the work.
  const bool symmetric = rows_are_d2_equivariant(grid, d.B, kEquivarianceTol);
  std::vector<int> rows;
  Eigen::VectorXd weight;
  if (symmetric) {
    const auto reps = d2_representatives(grid);
    weight.resize(static_cast<Eigen::Index>(reps.size()));
    for (size_t k = 0; k < reps.size(); ++k) {
      rows.push_back(reps[k].cell);
      weight[static_cast<Eigen::Index>(k)] = reps[k].weight * d.W[reps[k].cell];
    }
  } else {
    weight = d.W;
    for (int c = 0; c < cells; ++c) rows.push_back(c);
  }
  const int n_rows = static_cast<int>(rows.size());
  Eigen::MatrixXd wb(n_rows, modes);
  for (int k = 0; k < n_rows; ++k) wb.row(k) = std::sqrt(weight[k]) * d.B.row(rows[static_cast<size_t>(k)]);
  const int per_block = (n_rows + kGramBlocks - 1) / kGramBlocks;
  std::vector<Eigen::MatrixXd> partial(kGramBlocks);
#pragma omp parallel for schedule(dynamic)
  for (int k = 0; k < kGramBlocks; ++k) {
    const int r0 = std::min(n_rows, k * per_block), r1 = std::min(n_rows, r0 + per_block);
    partial[static_cast<size_t>(k)] = Eigen::MatrixXd::Zero(modes, modes);
    if (r1 > r0) partial[static_cast<size_t>(k)].selfadjointView<Eigen::Lower>().rankUpdate(wb.middleRows(r0, r1 - r0).transpose());
  }
  Eigen::MatrixXd lower = Eigen::MatrixXd::Zero(modes, modes);
  for (const auto& p : partial) lower += p;
  d.G = lower.selfadjointView<Eigen::Lower>();
  if (symmetric) d.G = d2_average(d.G);
  d.gram_error = (d.G - Eigen::MatrixXd::Identity(modes, modes)).cwiseAbs().maxCoeff();
  const auto [lo, hi] = extreme_eigenvalues(d.G);
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
