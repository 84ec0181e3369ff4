#include "icobrdf/blas/blas_dense_kernels.hpp"

#include <cblas.h>

#include <algorithm>
#include <cctype>
#include <climits>
#include <string>

#include <Eigen/Core>

#include "icobrdf/core/support/build_isa.hpp"
#include "icobrdf/core/support/error.hpp"

extern "C" void dpotrf_(const char* uplo, const blasint* n, double* a, const blasint* lda, blasint* info);
extern "C" char* openblas_get_corename();

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

std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

}  // namespace

const DenseKernels& blas_dense_kernels() {
  static const DenseKernels k{"OpenBLAS", &blas_rank_update, &blas_cholesky_lower, true};
  return k;
}

int blas_kernel_vector_bits(std::string_view core_name) {
  const std::string n = lower(core_name);
  for (const char* c : {"skylakex", "cooperlake", "sapphirerapids"})
    if (n == c) return 512;
  for (const char* c : {"haswell", "zen", "excavator"})
    if (n == c) return 256;
  for (const char* c : {"katmai", "coppermine", "northwood", "prescott", "banias", "atom", "core2", "penryn", "dunnington",
                        "nehalem", "athlon", "opteron", "opteron_sse3", "barcelona", "nano", "sandybridge", "bulldozer",
                        "piledriver", "steamroller"})
    if (n == c) return 128;
  return 0;
}

BlasKernel widest_blas_kernel_for_cpu() {
  if (cpu_supports("avx512f") && cpu_supports("avx512bw") && cpu_supports("avx512dq") && cpu_supports("avx512vl")) return {"SkylakeX", 512};
  if (cpu_supports("avx2") && cpu_supports("fma")) return {"Haswell", 256};
  return {};
}

int eigen_vector_bits() {
#if defined(EIGEN_VECTORIZE_AVX512)
  return 512;
#elif defined(EIGEN_VECTORIZE_AVX)
  return 256;
#else
  return 128;
#endif
}

FitKernelChoice choose_fit_kernels(std::string_view core_name, int eigen_bits) {
  const int blas_bits = blas_kernel_vector_bits(core_name);
  const std::string core = "OpenBLAS's " + std::string(core_name) + " kernel";
  const std::string eigen = "Eigen's " + std::to_string(eigen_bits) + "-bit code";
  FitKernelChoice c;
  if (blas_bits == 0) {
    c.kernels = &eigen_dense_kernels();
    c.reason = "Eigen: " + core + " is not one whose vector width is known here";
  } else if (blas_bits >= eigen_bits && eigen_bits > 0) {
    c.kernels = &blas_dense_kernels();
    c.reason = "OpenBLAS: " + core + " uses " + std::to_string(blas_bits) + "-bit vectors (" + eigen + ": " +
               std::to_string(eigen_bits) + ")";
  } else {
    c.kernels = &eigen_dense_kernels();
    c.reason = "Eigen: " + core + " uses " + std::to_string(blas_bits) + "-bit vectors, narrower than " + eigen +
               " (a CPU newer than the OpenBLAS build, or OPENBLAS_CORETYPE)";
  }
  return c;
}

const FitKernelChoice& fit_kernel_choice() {
  static const FitKernelChoice c = choose_fit_kernels(openblas_get_corename(), eigen_vector_bits());
  return c;
}

const DenseKernels& fit_dense_kernels() { return *fit_kernel_choice().kernels; }

}  // namespace icobrdf
