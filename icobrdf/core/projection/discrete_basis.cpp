#include "icobrdf/core/projection/discrete_basis.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>
#include <string>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/horizon.hpp"
#include "icobrdf/core/basis/grid_symmetry.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/support/huge_pages.hpp"

namespace icobrdf {

namespace {

// Cells per block of the Gram product: each block adds (W^1/2 B)_block^T (W^1/2 B)_block; blocks are summed
// in a fixed order so G does not depend on the number of threads.
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


// The D2 maps form the group: each is an involution on the cells and rotate_pi = mirror_xz o mirror_yz.
bool d2_maps_form_group(const Grid& g) {
  if (!has_d2_maps(g)) return false;
  const int n = g.cells();
  for (int c = 0; c < n; ++c) {
    const int r = g.rotate_pi[c], a = g.mirror_xz[c], b = g.mirror_yz[c];
    if (r < 0 || r >= n || a < 0 || a >= n || b < 0 || b >= n) return false;
    if (g.rotate_pi[r] != c || g.mirror_xz[a] != c || g.mirror_yz[b] != c || g.mirror_xz[b] != r) return false;
  }
  return true;
}

// How to fill the rows of a cell that is not a representative: B_cell = sign_map B_rep.
struct OrbitFill {
  int rep;   // index into the representatives
  int cell;
  int map;   // index into d2_maps
};

// For every representative and every other cell of its orbit, the first map that sends the representative
// there carrying the image of its cubature (cubature_is_image, icobrdf/core/basis/grid_symmetry.hpp; a cell reached by
// two maps, as when the representative lies on a mirror, needs only one of them). Empty when some orbit cell has none: the rows must then be evaluated.
std::vector<OrbitFill> orbit_fill_plan(const Grid& g, const std::vector<D2Representative>& reps) {
  const auto maps = d2_maps(g);
  const int nr = static_cast<int>(reps.size());
  std::vector<std::vector<OrbitFill>> per(static_cast<size_t>(nr));
  bool ok = true;
#pragma omp parallel for schedule(static) reduction(&& : ok) if (g.cubature_points.rows() > 100000)
  for (int k = 0; k < nr; ++k) {
    const int c = reps[static_cast<size_t>(k)].cell;
    for (int s = 0; s < static_cast<int>(maps.size()) && ok; ++s) {
      const int t = (*maps[static_cast<size_t>(s)].cells)[c];
      bool seen = t == c;
      for (const auto& f : per[static_cast<size_t>(k)]) seen = seen || f.cell == t;
      if (seen) continue;
      int found = -1;
      for (int u = s; u < static_cast<int>(maps.size()) && found < 0; ++u)
        if ((*maps[static_cast<size_t>(u)].cells)[c] == t && cubature_is_image(g, maps[static_cast<size_t>(u)], c, t)) found = u;
      if (found < 0) ok = false;
      else per[static_cast<size_t>(k)].push_back({k, t, found});
    }
  }
  std::vector<OrbitFill> plan;
  if (!ok) return plan;
  for (const auto& p : per) plan.insert(plan.end(), p.begin(), p.end());
  return plan;
}

// Row of B for cell c: the cubature's weighted sum of K_j divided by the solid angle.
void cell_average(const Grid& g, int order, int c, double* out) {
  const auto b = g.cubature_offsets[static_cast<size_t>(c)], e = g.cubature_offsets[static_cast<size_t>(c) + 1];
  hemisphere_basis_weighted_sum(order, e - b, g.cubature_points.data() + 3 * b, g.cubature_weights.data() + b, out);
  const double omega = g.solid_angles[c];
  const int m = hemisphere_basis_count(order);
  for (int j = 0; j < m; ++j) out[j] /= omega;
}

// B and G from one cell per D2 orbit, when the grid's cubature is equivariant (cubature_is_image): the representatives'
// rows are evaluated (R, representatives x modes), every other row is a representative's times the mode
// signs, and G = d2_average(X) with X = sum_rep (W_c / |stabilizer|) R_c^T R_c, of which only the blocks
// within a symmetry class are needed (d2_average zeroes the rest). Returns false (nothing written) when a
// cell fixed by a map has a row that is not invariant under it to kEquivarianceTol (an asymmetric rule).
bool build_from_orbits(const Grid& grid, DiscreteBasis& d) {
  const int modes = hemisphere_basis_count(d.order);
  const auto reps = d2_representatives(grid);
  const auto plan = orbit_fill_plan(grid, reps);
  if (plan.empty() && static_cast<int>(reps.size()) < grid.cells()) return false;
  const int nr = static_cast<int>(reps.size());
  const auto maps = d2_maps(grid);
  std::vector<std::vector<double>> sign(maps.size(), std::vector<double>(static_cast<size_t>(modes)));
  for (size_t s = 0; s < maps.size(); ++s)
    for (int j = 0; j < modes; ++j) sign[s][static_cast<size_t>(j)] = maps[s].sign(ansi_to_nl(j).l);
  Eigen::MatrixXd r(nr, modes);  // representatives x modes
  advise_huge_pages(r.data(), sizeof(double) * static_cast<size_t>(r.size()));
  // Groups of kRowGroup representatives: their rows are stored column by column, one cache line per column.
  constexpr int kRowGroup = 8;
#pragma omp parallel
  {
    std::vector<double> rows(static_cast<size_t>(modes) * kRowGroup);
#pragma omp for schedule(dynamic, 2)
    for (int k0 = 0; k0 < nr; k0 += kRowGroup) {
      const int count = std::min(kRowGroup, nr - k0);
      for (int k = 0; k < count; ++k) cell_average(grid, d.order, reps[static_cast<size_t>(k0 + k)].cell, rows.data() + static_cast<size_t>(k) * modes);
      for (int j = 0; j < modes; ++j)
        for (int k = 0; k < count; ++k) r(k0 + k, j) = rows[static_cast<size_t>(k) * modes + j];
    }
  }
  // A representative fixed by a map must have zero average for the modes that map reverses.
  const double bound = kEquivarianceTol * std::max(1e-300, r.cwiseAbs().maxCoeff());
  for (int k = 0; k < nr; ++k)
    for (size_t s = 0; s < maps.size(); ++s)
      if ((*maps[s].cells)[reps[static_cast<size_t>(k)].cell] == reps[static_cast<size_t>(k)].cell)
        for (int j = 0; j < modes; ++j)
          if (sign[s][static_cast<size_t>(j)] < 0 && std::abs(r(k, j)) > bound) return false;
  // Source of each row of B: representative src_rep[c] times the signs of map src_map[c] (0 = identity,
  // 1 + index into maps). Columns are then written in cell order.
  std::vector<int> src_rep(static_cast<size_t>(grid.cells()), -1), src_map(static_cast<size_t>(grid.cells()), 0);
  for (int k = 0; k < nr; ++k) src_rep[static_cast<size_t>(reps[static_cast<size_t>(k)].cell)] = k;
  for (const auto& f : plan) {
    src_rep[static_cast<size_t>(f.cell)] = f.rep;
    src_map[static_cast<size_t>(f.cell)] = 1 + f.map;
  }
  if (std::find(src_rep.begin(), src_rep.end(), -1) != src_rep.end()) return false;  // a cell outside every orbit
  d.B.resize(grid.cells(), modes);
  advise_huge_pages(d.B.data(), sizeof(double) * static_cast<size_t>(d.B.size()));
#pragma omp parallel for schedule(static)
  for (int j = 0; j < modes; ++j) {
    const double sg[4] = {1.0, sign[0][static_cast<size_t>(j)], sign[1][static_cast<size_t>(j)], sign[2][static_cast<size_t>(j)]};
    double* col = d.B.col(j).data();
    const double* rc = r.col(j).data();
    for (int c = 0; c < grid.cells(); ++c) col[c] = sg[src_map[static_cast<size_t>(c)]] * rc[src_rep[static_cast<size_t>(c)]];
  }
  // Within-class blocks of G and their extreme eigenvalues, one class per task.
  std::vector<std::vector<int>> idx(4);
  for (int j = 0; j < modes; ++j) idx[static_cast<size_t>(d2_class(j))].push_back(j);
  Eigen::VectorXd sw(nr);
  for (int k = 0; k < nr; ++k) sw[k] = std::sqrt(reps[static_cast<size_t>(k)].weight * grid.solid_angles[reps[static_cast<size_t>(k)].cell]);
  d.G = Eigen::MatrixXd::Zero(modes, modes);
  double lo[4], hi[4];
#pragma omp parallel for schedule(dynamic)
  for (int cls = 0; cls < 4; ++cls) {
    const auto& id = idx[static_cast<size_t>(cls)];
    const int s = static_cast<int>(id.size());
    lo[cls] = std::numeric_limits<double>::infinity();
    hi[cls] = -lo[cls];
    if (s == 0) continue;
    Eigen::MatrixXd wb(nr, s);
    for (int a = 0; a < s; ++a) wb.col(a) = sw.cwiseProduct(r.col(id[static_cast<size_t>(a)]));
    Eigen::MatrixXd x = Eigen::MatrixXd::Zero(s, s);
    x.selfadjointView<Eigen::Lower>().rankUpdate(wb.transpose(), 4.0);  // d2_average: 4 X within a class
    x = x.selfadjointView<Eigen::Lower>();
    for (int b = 0; b < s; ++b)
      for (int a = 0; a < s; ++a) d.G(id[static_cast<size_t>(a)], id[static_cast<size_t>(b)]) = x(a, b);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(x, Eigen::EigenvaluesOnly);
    lo[cls] = eig.eigenvalues().minCoeff();
    hi[cls] = eig.eigenvalues().maxCoeff();
  }
  const double lmin = std::min(std::min(lo[0], lo[1]), std::min(lo[2], lo[3]));
  const double lmax = std::max(std::max(hi[0], hi[1]), std::max(hi[2], hi[3]));
  d.gram_error = (d.G - Eigen::MatrixXd::Identity(modes, modes)).cwiseAbs().maxCoeff();
  d.condition = lmin > 0.0 ? lmax / lmin : std::numeric_limits<double>::infinity();
  d.evaluated_cells = nr;
  return true;
}

}  // namespace

DiscreteBasis build_discrete_basis(const Grid& grid, int order) {
  if (order < 0) throw ArgumentError("discrete basis: order expected >= 0, got " + std::to_string(order));
  const int cells = grid.cells();
  const int modes = hemisphere_basis_count(order);
  // Validate up front: nothing may throw inside the parallel loop.
  if (const Eigen::Index q = first_invalid_direction(grid.cubature_points, kHorizonSlack); q >= 0)
    throw ArgumentError("discrete basis: cubature point " + std::to_string(q) + " is not a finite direction with z >= 0");
  DiscreteBasis d;
  d.order = order;
  d.W = grid.solid_angles;
  // On a D2-symmetric grid whose cubature is equivariant (cubature_is_image), a quarter of the cells suffice.
  if (d2_maps_form_group(grid) && build_from_orbits(grid, d)) return d;
  d.evaluated_cells = cells;
  std::vector<int> all(static_cast<size_t>(cells));
  for (int c = 0; c < cells; ++c) all[static_cast<size_t>(c)] = c;
  d.B = basis_rows(grid, order, all);
  // G = B^T W B as a sum of symmetric rank updates over fixed blocks of cells (lower triangle, then
  // mirrored). On a D2-symmetric grid whose B is equivariant (icobrdf/core/basis/grid_symmetry.hpp) only one cell per
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
  const int per_block = (n_rows + kGramPartialSums - 1) / kGramPartialSums;
  std::vector<Eigen::MatrixXd> partial(kGramPartialSums);
#pragma omp parallel for schedule(dynamic)
  for (int k = 0; k < kGramPartialSums; ++k) {
    const int r0 = std::min(n_rows, k * per_block), r1 = std::min(n_rows, r0 + per_block);
    partial[static_cast<size_t>(k)] = Eigen::MatrixXd::Zero(modes, modes);
    if (r1 > r0) partial[static_cast<size_t>(k)].selfadjointView<Eigen::Lower>().rankUpdate(wb.middleRows(r0, r1 - r0).transpose());
  }
  Eigen::MatrixXd lower = Eigen::MatrixXd::Zero(modes, modes);
  for (const auto& p : partial) lower += p;
  d.G = lower.selfadjointView<Eigen::Lower>();
  if (symmetric) d.G = d2_average(d.G);
  set_gram_figures(d);
  return d;
}

Eigen::MatrixXd basis_rows(const Grid& grid, int order, const std::vector<int>& cells) {
  if (order < 0) throw ArgumentError("basis rows: order expected >= 0, got " + std::to_string(order));
  for (const int c : cells)
    if (c < 0 || c >= grid.cells())
      throw ArgumentError("basis rows: cell " + std::to_string(c) + " outside the grid's " + std::to_string(grid.cells()));
  if (const Eigen::Index q = first_invalid_direction(grid.cubature_points, kHorizonSlack); q >= 0)
    throw ArgumentError("basis rows: cubature point " + std::to_string(q) + " is not a finite direction with z >= 0");
  const int n = static_cast<int>(cells.size()), modes = hemisphere_basis_count(order);
  Eigen::MatrixXd b(n, modes);
  advise_huge_pages(b.data(), sizeof(double) * static_cast<size_t>(b.size()));
#pragma omp parallel
  {
    std::vector<double> row(static_cast<size_t>(modes));
#pragma omp for schedule(dynamic, 16)
    for (int k = 0; k < n; ++k) {
      cell_average(grid, order, cells[static_cast<size_t>(k)], row.data());
      for (int j = 0; j < modes; ++j) b(k, j) = row[static_cast<size_t>(j)];
    }
  }
  return b;
}

void set_gram_figures(DiscreteBasis& d) {
  d.gram_error = (d.G - Eigen::MatrixXd::Identity(d.G.rows(), d.G.cols())).cwiseAbs().maxCoeff();
  const auto [lo, hi] = extreme_eigenvalues(d.G);
  d.condition = lo > 0.0 ? hi / lo : std::numeric_limits<double>::infinity();
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
