#pragma once
// The dense kernels of the least-squares fits (icobrdf/core/fit/dense_kernels.hpp) from OpenBLAS: dsyrk for the
// rank-k updates of the normal equations and LAPACK's dpotrf for the Cholesky factorizations. Each call runs
// on OpenBLAS's own threads (all cores unless OPENBLAS_NUM_THREADS says otherwise), so `threaded` is set and
// the fits call them from one thread at a time. Results agree with Eigen's kernels to rounding (the sums run
// in another order).
//
// Which set a fit uses: fit_dense_kernels(), which the icobrdf program and the Python module install at start-up
// as core's default dense kernels (set_default_dense_kernels), the set io's measured SOURCEs hand to their fits.
// This library (icobrdf::blas) depends on core alone; io and the layers above it never name BLAS. OpenBLAS picks its kernel when the library loads, from the CPU
// it recognizes (or OPENBLAS_CORETYPE). A CPU newer than the OpenBLAS build gets a generic fallback: Debian's
// OpenBLAS 0.3.21 runs its SSE3 "Prescott" kernel on an Emerald Rapids Xeon, where dsyrk at 2,211 unknowns
// measured 15-26 GFLOP/s on 2 threads against 80-93 for Eigen's kernel (icobrdf/core/fit/dense_kernels.hpp) and 61-72
// for OpenBLAS's own SkylakeX kernel under load (benchmarks/RESULTS.md, "Dense kernels of the sample fits").
// So OpenBLAS serves the fits only when its kernel
// uses vectors at least as wide as Eigen's in this build; otherwise Eigen's kernels do. The choice depends
// only on the build, the CPU and the environment, never on a timing, so fits stay reproducible on a machine.
#include <string>
#include <string_view>

#include "icobrdf/core/fit/dense_kernels.hpp"

namespace icobrdf {

const DenseKernels& blas_dense_kernels();

// The FP64 vector width (bits) of the DGEMM kernel of an OpenBLAS core name (openblas_get_corename(), any
// case): 512 for the AVX-512 kernels (SkylakeX, Cooperlake, SapphireRapids), 256 for the AVX2 + FMA kernels
// (Haswell, Zen, Excavator), 128 for the SSE and first-generation AVX ones (Prescott ... Sandybridge,
// Bulldozer, Piledriver, Steamroller: no FMA3 in their DGEMM kernels), 0 for a name not known here.
int blas_kernel_vector_bits(std::string_view core_name);

// The OpenBLAS core name whose DGEMM kernel uses the widest vectors this CPU runs, with that width: SkylakeX
// (512) with AVX-512 F/BW/DQ/VL, Haswell (256) with AVX2 + FMA, {"", 0} otherwise. For naming in
// OPENBLAS_CORETYPE when OpenBLAS's own choice is a narrower fallback.
struct BlasKernel {
  std::string core;
  int vector_bits = 0;
};
BlasKernel widest_blas_kernel_for_cpu();

// The vector width (bits) Eigen's matrix products use in this build (its compile-time ISA): 512, 256 or 128.
int eigen_vector_bits();

struct FitKernelChoice {
  const DenseKernels* kernels = nullptr;  // blas_dense_kernels() or eigen_dense_kernels()
  std::string reason;                     // one line: which, and why (names OpenBLAS's core)
};

// The rule above for the running process (OpenBLAS's core as loaded, Eigen's width as built); computed once.
const FitKernelChoice& fit_kernel_choice();
// The rule for given inputs (tests): OpenBLAS when blas_kernel_vector_bits(core_name) >= eigen_bits > 0.
FitKernelChoice choose_fit_kernels(std::string_view core_name, int eigen_bits);
// fit_kernel_choice().kernels.
const DenseKernels& fit_dense_kernels();

}  // namespace icobrdf
