#include "icobrdf/io/blas_dense_kernels.hpp"

#include <cblas.h>

#include <climits>
#include <string>

#include "icobrdf/core/error.hpp"

extern "C" void dpotrf_(const char* uplo, const blasint* n, double* a, const blasint* lda, blasint* info);

namespace icobrdf {

namespace {

// OpenBLAS's interface takes 32-bit sizes.
blasint blas_size(Eigen::Index n, const char* what) {
  if (n < 0 || n > INT_MAX) throw UnsupportedError(std::string("BLAS kernels: ") + what + " " + std::to_string(n) + " exceeds the 32-bit BLAS interface");
  return static_cast<blasint>(n);
}

void blas_rank_update(double* g, Eigen::Index k, const double* a, Eigen::Index rows, Eigen::Index lda) {
  cblas_dsyrk(CblasColMajor, CblasLower, CblasTrans, blas_size(k, "order"), blas_size(rows, "rows"), 1.0, a, blas_size(lda, "stride"),
              1.0, g, blas_size(k, "order"));
}

bool blas_cholesky_lower(double* g, Eigen::Index k) {
  const blasint n = blas_size(k, "order");
  blasint info = 0;
  dpotrf_("L", &n, g, &n, &info);
  if (info < 0) throw ArgumentError("BLAS kernels: dpotrf rejected argument " + std::to_string(-info));
  return info == 0;
}

}  // namespace

const DenseKernels& blas_dense_kernels() {
  static const DenseKernels k{"OpenBLAS", &blas_rank_update, &blas_cholesky_lower, true};
  return k;
}

}  // namespace icobrdf
