#pragma once
// The dense kernels of the least-squares fits (icobrdf/core/dense_kernels.hpp) from OpenBLAS: dsyrk for the
// rank-k updates of the normal equations and LAPACK's dpotrf for the Cholesky factorizations. Each call runs
// on OpenBLAS's own threads (all cores unless OPENBLAS_NUM_THREADS says otherwise), so `threaded` is set and
// the fits call them from one thread at a time. Measured on AVX-512 (2 cores, 2,211 unknowns): the update at
// about 0.85 of the FP64 peak against Eigen's 0.6 (benchmarks/RESULTS.md, "The 20,000-sample order-10 fit").
// Results agree with Eigen's kernels to rounding (the sums run in another order).
#include "icobrdf/core/dense_kernels.hpp"

namespace icobrdf {

const DenseKernels& blas_dense_kernels();

}  // namespace icobrdf
