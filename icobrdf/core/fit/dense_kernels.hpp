#pragma once
// The two dense kernels whose speed decides a large least-squares fit (icobrdf/core/fit/sample_fit.hpp): the
// symmetric rank-k update G += A^T A and the Cholesky factorization G = L L^T. icobrdf_core computes them with
// Eigen: the update in blocks of columns on all threads (Eigen's own symmetric update runs on one thread),
// the factorization blocked with that parallel update for its trailing matrix. Measured at 2,211 unknowns on
// an idle 2-core AVX-512 Xeon: the update at 80-93 GFLOP/s, about 0.5 of the measured FP64 peak of 166-175
// (Eigen's own update 43.5), the factorization at 39 (Eigen's LLT 25) (benchmarks/bench_dense_kernels). The
// optional library icobrdf::blas (icobrdf/blas/blas_dense_kernels.hpp) holds OpenBLAS's; a fit takes a set through
// SampleFitOptions::kernels, and a program that links icobrdf::blas installs its choice once as the process-wide
// default (set_default_dense_kernels) that io's measured SOURCEs hand to their fits. Both kernels compute the same
// mathematical result; they differ in the order of the sums, so results agree to rounding, not bitwise.
#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace icobrdf {

struct DenseKernels {
  const char* name = "";
  // g (k x k, column-major, leading dimension k) += a^T a on the lower triangle (the strict upper triangle is
  // left as it was); a: rows x k, column-major, leading dimension lda >= rows.
  void (*rank_update)(double* g, Eigen::Index k, const double* a, Eigen::Index rows, Eigen::Index lda) = nullptr;
  // Overwrites the lower triangle of g (k x k, column-major) with L, G = L L^T, reading only the lower
  // triangle; returns false when G is not (numerically) positive definite.
  bool (*cholesky_lower)(double* g, Eigen::Index k) = nullptr;
  // True when the kernels run a call on threads of their own (OpenBLAS's), which calls from several threads at
  // once would oversubscribe: callers then call them from one thread at a time. Eigen's kernels use OpenMP,
  // which runs a call made inside a parallel region on the calling thread, so they may be called in parallel.
  bool threaded = false;
};

// Eigen's kernels (the default when a fit is given none).
const DenseKernels& eigen_dense_kernels();

// The process-wide default set: what the fits of io's measured SOURCEs (MERL tables, CSV samples) are handed.
// Eigen's until a program installs another at start-up (the icobrdf program and the Python module install
// icobrdf::blas's fit_dense_kernels()); null restores Eigen's. `kernels` must outlive its use as the default.
// Safe to read from any thread; install it before fits start, since a fit running meanwhile keeps the set it took.
void set_default_dense_kernels(const DenseKernels* kernels);
const DenseKernels& default_dense_kernels();

// g += a^T a on g's lower triangle, with `kernels` (Eigen's when null). g must be square with a's columns.
void rank_update_lower(const DenseKernels* kernels, Eigen::MatrixXd& g, const Eigen::Ref<const Eigen::MatrixXd>& a);

// g += a^T a on g's lower triangle in single precision (float products and sums), with Eigen's kernel in blocks
// of columns on all threads; about twice the double update's speed (AVX-512: 16 lanes instead of 8). For the
// Gram matrices of large sample fits whose rounding the fit then removes (icobrdf/core/fit/sample_fit.hpp,
// GramProducts::Single). ArgumentError when g is not square with a's columns.
void rank_update_lower(Eigen::MatrixXf& g, const Eigen::Ref<const Eigen::MatrixXf>& a);

// The Cholesky factorization of the symmetric g (lower triangle read) as an Eigen::LLT, computed by `kernels`
// (Eigen's when null): solve(), matrixL(), rcond() and info() behave as for Eigen::LLT(g). g is taken by value
// (move a temporary in: the factor is computed in its storage).
Eigen::LLT<Eigen::MatrixXd> cholesky(const DenseKernels* kernels, Eigen::MatrixXd g);

// The same in single precision with Eigen's kernels (the blocked factorization with the parallel trailing update),
// about twice as fast: a factor whose rounding (~ unknowns x 6e-8 relative, times cond(G) in a solve) a caller
// removes by refinement against a double residual (the cross-validation folds of icobrdf/core/fit/sample_fit_selection.hpp).
Eigen::LLT<Eigen::MatrixXf> cholesky(Eigen::MatrixXf g);

}  // namespace icobrdf
