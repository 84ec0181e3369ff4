#pragma once
// Four doubles as one value (GCC/clang vector extension: one AVX register, or two SSE2 registers without AVX),
// with the few operations the batch kernels share (icobrdf/core/hemisphere_basis_block.cpp, icobrdf/core/spectrum_ops.cpp).
// Internal to core: include only from .cpp files.
#include <cstring>

// Without AVX (ICOBRDF_NATIVE=OFF) GCC notes that 32-byte vectors are passed differently; these helpers are
// inline and internal to core, so the ABI note does not apply.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

namespace icobrdf::simd4 {

typedef double v4d __attribute__((vector_size(32)));
typedef long long v4l __attribute__((vector_size(32)));

inline v4d splat(double a) { return v4d{a, a, a, a}; }
// Unaligned load and store of four doubles.
inline v4d load4(const double* p) {
  v4d r;
  std::memcpy(&r, p, sizeof r);
  return r;
}
inline void storeu(double* p, v4d a) { std::memcpy(p, &a, sizeof a); }

}  // namespace icobrdf::simd4
