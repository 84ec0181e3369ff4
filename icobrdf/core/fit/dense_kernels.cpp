#include "icobrdf/core/fit/dense_kernels.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>
#include <utility>

#include "icobrdf/core/support/error.hpp"

namespace icobrdf {

namespace {

// Columns of G per block of the rank update: each block is a small triangle (Eigen's rank update) over a
// rectangle below it (one matrix product of ~k x depth x kRankUpdateBlock), wide enough for the product to run
// at its register-blocked speed (96: 68 GFLOP/s, 192: 81-93, 384: 79 on the 2-core AVX-512 Xeon of
// benchmarks/RESULTS.md, "Dense kernels of the sample fits").
constexpr Eigen::Index kRankUpdateBlock = 192;
// Below this many multiply-adds (size^2 x depth / 2) the blocks run on one thread: a parallel region costs more.
constexpr double kParallelRankUpdateMinWork = 2e7;

// g += alpha b b^T on g's lower triangle (g: n x n, b: n x depth). Eigen runs a symmetric rank update on one
// thread (only its general products are parallel), so blocks of columns run on all threads instead; each
// entry of g is summed by one block, in an order fixed by the blocking alone, so the result does not depend
// on the thread count. Called inside a parallel region, it runs on the calling thread.
template <class G, class B, class Scalar>
void lower_rank_update(G g, const B& b, Scalar alpha) {
  const Eigen::Index n = g.rows(), blocks = (n + kRankUpdateBlock - 1) / kRankUpdateBlock;
  const bool parallel = 0.5 * static_cast<double>(n) * static_cast<double>(n) * static_cast<double>(b.cols()) >= kParallelRankUpdateMinWork;
  // Blocks in order, the largest (leftmost) first, one at a time per thread.
#pragma omp parallel for schedule(dynamic, 1) if (parallel)
  for (Eigen::Index blk = 0; blk < blocks; ++blk) {
    const Eigen::Index j0 = blk * kRankUpdateBlock, w = std::min(kRankUpdateBlock, n - j0), below = n - j0 - w;
    g.block(j0, j0, w, w).template selfadjointView<Eigen::Lower>().rankUpdate(b.middleRows(j0, w), alpha);
    if (below > 0) g.block(j0 + w, j0, below, w).noalias() += alpha * b.middleRows(j0 + w, below) * b.middleRows(j0, w).transpose();
  }
}

void eigen_rank_update(double* g, Eigen::Index k, const double* a, Eigen::Index rows, Eigen::Index lda) {
  Eigen::Map<Eigen::MatrixXd> gm(g, k, k);
  const Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>> am(a, rows, k, Eigen::OuterStride<>(lda));
  lower_rank_update(Eigen::Ref<Eigen::MatrixXd>(gm), am.transpose(), 1.0);
}

// Columns per panel of the blocked Cholesky factorization: the panel is factored by Eigen (one thread), the
// column below it solved against it, and the trailing matrix updated by lower_rank_update (all threads).
constexpr Eigen::Index kCholeskyPanel = 192;

// Right-looking blocked Cholesky, lower triangle in place. Eigen's own blocked LLT updates its trailing
// matrix with its one-thread symmetric rank update; this one spreads that update, nearly all of the k^3 / 3
// flops, over the threads. The order of every sum is fixed by the panel and block widths, not the threads.
template <class Scalar>
bool blocked_cholesky_lower(Scalar* g, Eigen::Index k) {
  using Matrix = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;
  Eigen::Map<Matrix> a(g, k, k);
  for (Eigen::Index j = 0; j < k; j += kCholeskyPanel) {
    const Eigen::Index w = std::min(kCholeskyPanel, k - j), r = k - j - w;
    auto a11 = a.block(j, j, w, w);
    if (Eigen::internal::llt_inplace<Scalar, Eigen::Lower>::blocked(a11) != -1) return false;
    if (r == 0) break;
    auto a21 = a.block(j + w, j, r, w);
    a11.template triangularView<Eigen::Lower>().transpose().template solveInPlace<Eigen::OnTheRight>(a21);  // a21 L11^-T
    lower_rank_update(Eigen::Ref<Matrix>(a.block(j + w, j + w, r, r)), a21, Scalar(-1));
  }
  return true;
}

bool eigen_cholesky_lower(double* g, Eigen::Index k) { return blocked_cholesky_lower(g, k); }

// An Eigen::LLT whose factor was computed elsewhere: Eigen 3.4 keeps the factor, the L1 norm of the matrix
// (for rcond) and the status in protected members, which a derived class may set. It adds no member, so the
// object converts to a plain Eigen::LLT without loss.
template <class Matrix>
class FactoredLlt : public Eigen::LLT<Matrix> {
 public:
  FactoredLlt(Matrix factor, typename Matrix::RealScalar l1_norm, bool ok) {
    this->m_matrix = std::move(factor);
    this->m_l1_norm = l1_norm;
    this->m_isInitialized = true;
    this->m_info = ok ? Eigen::Success : Eigen::NumericalIssue;
  }
};

// The L1 norm (largest absolute column sum) of the symmetric matrix whose lower triangle g holds, as
// Eigen::LLT::compute computes it; read column by column: g(i, j), i > j, counts in columns j and i.
template <class Matrix>
typename Matrix::RealScalar symmetric_l1_norm(const Matrix& g) {
  using Array = Eigen::Array<typename Matrix::RealScalar, Eigen::Dynamic, 1>;
  const Eigen::Index k = g.rows();
  if (k == 0) return 0;
  Array sums = Array::Zero(k);
  for (Eigen::Index j = 0; j < k; ++j) {
    const Array c = g.col(j).tail(k - j).array().abs();
    sums[j] += c.sum();
    sums.tail(k - j - 1) += c.tail(k - j - 1);
  }
  return sums.maxCoeff();
}

// g factored in place by `factor` (lower triangle) as an Eigen::LLT, with the L1 norm of g for rcond().
template <class Matrix>
Eigen::LLT<Matrix> factored_llt(Matrix g, bool (*factor)(typename Matrix::Scalar*, Eigen::Index)) {
  const auto l1 = symmetric_l1_norm(g);
  const bool ok = g.rows() == 0 || factor(g.data(), g.rows());
  return FactoredLlt<Matrix>(std::move(g), l1, ok);
}

}  // namespace

const DenseKernels& eigen_dense_kernels() {
  static const DenseKernels k{"Eigen", &eigen_rank_update, &eigen_cholesky_lower, false};
  return k;
}

namespace {
std::atomic<const DenseKernels*> g_default_kernels{nullptr};  // null: Eigen's
}  // namespace

void set_default_dense_kernels(const DenseKernels* kernels) { g_default_kernels.store(kernels, std::memory_order_release); }

const DenseKernels& default_dense_kernels() {
  const DenseKernels* k = g_default_kernels.load(std::memory_order_acquire);
  return k ? *k : eigen_dense_kernels();
}

void rank_update_lower(const DenseKernels* kernels, Eigen::MatrixXd& g, const Eigen::Ref<const Eigen::MatrixXd>& a) {
  if (g.rows() != g.cols() || g.cols() != a.cols())
    throw ArgumentError("rank update: G is " + std::to_string(g.rows()) + " x " + std::to_string(g.cols()) + ", A has " +
                        std::to_string(a.cols()) + " columns");
  if (a.rows() == 0 || a.cols() == 0) return;
  const DenseKernels& k = kernels ? *kernels : eigen_dense_kernels();
  k.rank_update(g.data(), g.rows(), a.data(), a.rows(), a.outerStride());
}

void rank_update_lower(Eigen::MatrixXf& g, const Eigen::Ref<const Eigen::MatrixXf>& a) {
  if (g.rows() != g.cols() || g.cols() != a.cols())
    throw ArgumentError("single-precision rank update: G is " + std::to_string(g.rows()) + " x " + std::to_string(g.cols()) +
                        ", A has " + std::to_string(a.cols()) + " columns");
  if (a.rows() == 0 || a.cols() == 0) return;
  lower_rank_update(Eigen::Ref<Eigen::MatrixXf>(g), a.transpose(), 1.0f);
}

Eigen::LLT<Eigen::MatrixXd> cholesky(const DenseKernels* kernels, Eigen::MatrixXd g) {
  if (g.rows() != g.cols())
    throw ArgumentError("Cholesky factorization: the matrix is " + std::to_string(g.rows()) + " x " + std::to_string(g.cols()) +
                        ", expected square");
  // Eigen's kernels: a matrix of one panel is Eigen's LLT itself (the blocked factorization would run the same
  // arithmetic); a larger one takes the blocked factorization with the parallel trailing update.
  if ((!kernels || kernels->cholesky_lower == eigen_dense_kernels().cholesky_lower) && g.rows() <= kCholeskyPanel)
    return Eigen::LLT<Eigen::MatrixXd>(g);
  if (!kernels) kernels = &eigen_dense_kernels();
  return factored_llt(std::move(g), kernels->cholesky_lower);
}

Eigen::LLT<Eigen::MatrixXf> cholesky(Eigen::MatrixXf g) {
  if (g.rows() != g.cols())
    throw ArgumentError("single-precision Cholesky factorization: the matrix is " + std::to_string(g.rows()) + " x " +
                        std::to_string(g.cols()) + ", expected square");
  if (g.rows() <= kCholeskyPanel) return Eigen::LLT<Eigen::MatrixXf>(g);
  return factored_llt(std::move(g), &blocked_cholesky_lower<float>);
}

}  // namespace icobrdf
