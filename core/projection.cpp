#include "core/projection.hpp"

#include <Eigen/Cholesky>
#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#endif
#include <algorithm>
#include <string>
#include <vector>

#include "core/error.hpp"

namespace icobrdf {
namespace {

// LUT columns per block of project_lut: enough blocks to balance two or more threads at level 4 and up,
// wide enough that the packing of P^T for each block costs little next to the block of F.
constexpr Eigen::Index kProjectColumns = 512;

#if defined(__AVX2__) && defined(__FMA__)
// T = P^T F_J (modes x w) for a block of w LUT columns, as dot products along the cells: both P's columns
// and F's columns are contiguous there, so neither is packed (a GEMM library packs the large F first).
// Register tile: 3 modes x 4 LUT columns, 12 accumulators of 4 cells each; cells in chunks of kDotCells
// so that the chunk of P (modes x kDotCells, 184 KB at order 8) stays in L2 while F's columns stream in
// once (chunks of 128, 256, 512 and 1024 cells measured: 512 was fastest). At level 5, order 8 this runs
// at 71-74% of the FP64 peak against 62-65% for Eigen's GEMM (benchmarks/RESULTS.md). Cells beyond a multiple of 4 and columns beyond a multiple of 4
// are added by plain loops / Eigen.
constexpr Eigen::Index kTileModes = 3, kTileColumns = 4, kDotCells = 512;

void pt_times_block(const Eigen::MatrixXd& p, const double* f, Eigen::Index ldf, Eigen::Index w, Eigen::MatrixXd& t,
                    std::vector<double>& acc) {
  const Eigen::Index cells = p.rows(), modes = p.cols();
  const Eigen::Index mgroups = (modes + kTileModes - 1) / kTileModes, wv = w / kTileColumns * kTileColumns;
  const Eigen::Index cv = cells / 4 * 4;  // cells handled by vectors
  constexpr Eigen::Index kTile = kTileModes * kTileColumns * 4;  // doubles of one tile's accumulators
  acc.assign(static_cast<size_t>(mgroups * (wv / kTileColumns) * kTile), 0.0);
  for (Eigen::Index k0 = 0; k0 < cv; k0 += kDotCells) {
    const Eigen::Index k1 = std::min(cv, k0 + kDotCells);
    for (Eigen::Index j0 = 0; j0 < wv; j0 += kTileColumns) {
      const double* f0 = f + (j0 + 0) * ldf;
      const double* f1 = f + (j0 + 1) * ldf;
      const double* f2 = f + (j0 + 2) * ldf;
      const double* f3 = f + (j0 + 3) * ldf;
      for (Eigen::Index g = 0; g < mgroups; ++g) {
        const Eigen::Index m0 = g * kTileModes;
        // A short last group repeats the last mode; its accumulators are never read.
        const double* p0 = p.data() + m0 * cells;
        const double* p1 = p.data() + std::min(m0 + 1, modes - 1) * cells;
        const double* p2 = p.data() + std::min(m0 + 2, modes - 1) * cells;
        double* a = acc.data() + (g * (wv / kTileColumns) + j0 / kTileColumns) * kTile;
        __m256d c00 = _mm256_loadu_pd(a + 0), c01 = _mm256_loadu_pd(a + 4), c02 = _mm256_loadu_pd(a + 8);
        __m256d c10 = _mm256_loadu_pd(a + 12), c11 = _mm256_loadu_pd(a + 16), c12 = _mm256_loadu_pd(a + 20);
        __m256d c20 = _mm256_loadu_pd(a + 24), c21 = _mm256_loadu_pd(a + 28), c22 = _mm256_loadu_pd(a + 32);
        __m256d c30 = _mm256_loadu_pd(a + 36), c31 = _mm256_loadu_pd(a + 40), c32 = _mm256_loadu_pd(a + 44);
        for (Eigen::Index k = k0; k < k1; k += 4) {
          const __m256d x0 = _mm256_loadu_pd(p0 + k), x1 = _mm256_loadu_pd(p1 + k), x2 = _mm256_loadu_pd(p2 + k);
          __m256d y = _mm256_loadu_pd(f0 + k);
          c00 = _mm256_fmadd_pd(x0, y, c00);
          c01 = _mm256_fmadd_pd(x1, y, c01);
          c02 = _mm256_fmadd_pd(x2, y, c02);
          y = _mm256_loadu_pd(f1 + k);
          c10 = _mm256_fmadd_pd(x0, y, c10);
          c11 = _mm256_fmadd_pd(x1, y, c11);
          c12 = _mm256_fmadd_pd(x2, y, c12);
          y = _mm256_loadu_pd(f2 + k);
          c20 = _mm256_fmadd_pd(x0, y, c20);
          c21 = _mm256_fmadd_pd(x1, y, c21);
          c22 = _mm256_fmadd_pd(x2, y, c22);
          y = _mm256_loadu_pd(f3 + k);
          c30 = _mm256_fmadd_pd(x0, y, c30);
          c31 = _mm256_fmadd_pd(x1, y, c31);
          c32 = _mm256_fmadd_pd(x2, y, c32);
        }
        _mm256_storeu_pd(a + 0, c00), _mm256_storeu_pd(a + 4, c01), _mm256_storeu_pd(a + 8, c02);
        _mm256_storeu_pd(a + 12, c10), _mm256_storeu_pd(a + 16, c11), _mm256_storeu_pd(a + 20, c12);
        _mm256_storeu_pd(a + 24, c20), _mm256_storeu_pd(a + 28, c21), _mm256_storeu_pd(a + 32, c22);
        _mm256_storeu_pd(a + 36, c30), _mm256_storeu_pd(a + 40, c31), _mm256_storeu_pd(a + 44, c32);
      }
    }
  }
  t.resize(modes, w);
  for (Eigen::Index g = 0; g < mgroups; ++g)
    for (Eigen::Index j0 = 0; j0 < wv; j0 += kTileColumns)
      for (Eigen::Index jj = 0; jj < kTileColumns; ++jj)
        for (Eigen::Index r = 0; r < kTileModes; ++r) {
          const Eigen::Index m = g * kTileModes + r;
          if (m >= modes) continue;
          const double* v = acc.data() + (g * (wv / kTileColumns) + j0 / kTileColumns) * kTile + (jj * kTileModes + r) * 4;
          double sum = (v[0] + v[1]) + (v[2] + v[3]);
          for (Eigen::Index k = cv; k < cells; ++k) sum += p(k, m) * f[(j0 + jj) * ldf + k];  // the last cells
          t(m, j0 + jj) = sum;
        }
  if (wv < w) {  // the last columns
    const Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>> rest(f + wv * ldf, cells, w - wv, Eigen::OuterStride<>(ldf));
    t.rightCols(w - wv).noalias() = p.transpose() * rest;
  }
}
#endif

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

Eigen::MatrixXd project_lut(const ProjectionOperator& proj, const Eigen::MatrixXd& lut) {
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
#pragma omp parallel
  {
    Eigen::MatrixXd t(modes, kProjectColumns);  // P^T F_J, per thread
    std::vector<double> acc;
#pragma omp for schedule(dynamic)
    for (Eigen::Index b = 0; b < blocks; ++b) {
      const Eigen::Index c0 = b * kProjectColumns, w = std::min(kProjectColumns, cells - c0);
#if defined(__AVX2__) && defined(__FMA__)
      pt_times_block(proj.P, lut.data() + c0 * cells, cells, w, t, acc);
#else
      t.resize(modes, w);
      t.noalias() = proj.P.transpose() * lut.middleCols(c0, w);
#endif
      partial[static_cast<size_t>(b)].noalias() = t * proj.P.middleRows(c0, w);
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
