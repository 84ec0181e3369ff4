#include "icobrdf/core/dense_kernels.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "icobrdf/core/error.hpp"

namespace icobrdf {

namespace {

// Columns of G per block of the rank update: each block is a small triangle (Eigen's rank update) over a
// rectangle below it (one matrix product of ~k x rows x kRankUpdateBlock), wide enough for the product to run
// at its register-blocked speed.
constexpr Eigen::Index kRankUpdateBlock = 192;
// Below this many multiply-adds (rows x k^2 / 2) the blocks run on one thread: a parallel region costs more.
constexpr double kParallelRankUpdateMinWork = 2e7;

// Eigen runs a symmetric rank update on one thread (only its general products are parallel). Blocks of
// columns run on all threads instead; each entry of G is summed by one block, in an order fixed by the
// blocking alone, so the result does not depend on the thread count.
void eigen_rank_update(double* g, Eigen::Index k, const double* a, Eigen::Index rows, Eigen::Index lda) {
  Eigen::Map<Eigen::MatrixXd> gm(g, k, k);
  const Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>> am(a, rows, k, Eigen::OuterStride<>(lda));
  const Eigen::Index blocks = (k + kRankUpdateBlock - 1) / kRankUpdateBlock;
  const bool parallel = 0.5 * static_cast<double>(rows) * static_cast<double>(k) * static_cast<double>(k) >= kParallelRankUpdateMinWork;
  // Blocks in order, the largest (leftmost) first, one at a time per thread.
#pragma omp parallel for schedule(dynamic, 1) if (parallel)
  for (Eigen::Index b = 0; b < blocks; ++b) {
    const Eigen::Index j0 = b * kRankUpdateBlock, w = std::min(kRankUpdateBlock, k - j0), below = k - j0 - w;
    gm.block(j0, j0, w, w).selfadjointView<Eigen::Lower>().rankUpdate(am.middleCols(j0, w).transpose());
    if (below > 0) gm.block(j0 + w, j0, below, w).noalias() += am.middleCols(j0 + w, below).transpose() * am.middleCols(j0, w);
  }
}

bool eigen_cholesky_lower(double* g, Eigen::Index k) {
  Eigen::Map<Eigen::MatrixXd> gm(g, k, k);
  return Eigen::internal::llt_inplace<double, Eigen::Lower>::blocked(gm) == -1;
}

// An Eigen::LLT whose factor was computed elsewhere: Eigen 3.4 keeps the factor, the L1 norm of the matrix
// (for rcond) and the status in protected members, which a derived class may set. It adds no member, so the
// object converts to a plain Eigen::LLT without loss.
class FactoredLlt : public Eigen::LLT<Eigen::MatrixXd> {
 public:
  FactoredLlt(Eigen::MatrixXd factor, double l1_norm, bool ok) {
    m_matrix = std::move(factor);
    m_l1_norm = l1_norm;
    m_isInitialized = true;
    m_info = ok ? Eigen::Success : Eigen::NumericalIssue;
  }
};

// The L1 norm (largest absolute column sum) of the symmetric matrix whose lower triangle g holds, as
// Eigen::LLT::compute computes it; read column by column: g(i, j), i > j, counts in columns j and i.
double symmetric_l1_norm(const Eigen::MatrixXd& g) {
  const Eigen::Index k = g.rows();
  if (k == 0) return 0.0;
  Eigen::ArrayXd sums = Eigen::ArrayXd::Zero(k);
  for (Eigen::Index j = 0; j < k; ++j) {
    const Eigen::ArrayXd c = g.col(j).tail(k - j).array().abs();
    sums[j] += c.sum();
    sums.tail(k - j - 1) += c.tail(k - j - 1);
  }
  return sums.maxCoeff();
}

}  // namespace

const DenseKernels& eigen_dense_kernels() {
  static const DenseKernels k{"Eigen", &eigen_rank_update, &eigen_cholesky_lower, false};
  return k;
}

void rank_update_lower(const DenseKernels* kernels, Eigen::MatrixXd& g, const Eigen::Ref<const Eigen::MatrixXd>& a) {
  if (g.rows() != g.cols() || g.cols() != a.cols())
    throw ArgumentError("rank update: G is " + std::to_string(g.rows()) + " x " + std::to_string(g.cols()) + ", A has " +
                        std::to_string(a.cols()) + " columns");
  if (a.rows() == 0 || a.cols() == 0) return;
  const DenseKernels& k = kernels ? *kernels : eigen_dense_kernels();
  k.rank_update(g.data(), g.rows(), a.data(), a.rows(), a.outerStride());
}

Eigen::LLT<Eigen::MatrixXd> cholesky(const DenseKernels* kernels, Eigen::MatrixXd g) {
  if (g.rows() != g.cols())
    throw ArgumentError("Cholesky factorization: the matrix is " + std::to_string(g.rows()) + " x " + std::to_string(g.cols()) +
                        ", expected square");
  if (!kernels || kernels->cholesky_lower == eigen_dense_kernels().cholesky_lower) return Eigen::LLT<Eigen::MatrixXd>(g);
  const double l1 = symmetric_l1_norm(g);
  const bool ok = g.rows() == 0 || kernels->cholesky_lower(g.data(), g.rows());
  return FactoredLlt(std::move(g), l1, ok);
}

}  // namespace icobrdf
