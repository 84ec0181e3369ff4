#pragma once
// The SIMD instruction sets of the run-time dispatched kernels (Google Highway dynamic dispatch): the
// projection tile (icobrdf/core/projection/projection_tile.hpp), the spectrum tile (icobrdf/core/spectrum/spectrum_tile.hpp), the block
// basis kernel (hemisphere_basis_block, hemisphere_basis_weighted_sum), the microfacet kernel (GGX and
// Beckmann at pairs, icobrdf/core/models/microfacet_kernel.hpp) and lab/'s FP64 peak loop. Each dispatched translation unit is
// compiled once per target of Highway's list for this build's baseline (with -march=native only the
// native target, otherwise SSSE3 .. AVX-512); on its first call a kernel picks the best target this CPU runs.
// Results differ between targets in rounding only (wider vectors sum the cells in a different order); for
// one target they are the same on any thread count.
#include <cstdint>
#include <string>
#include <vector>

namespace icobrdf {

struct SimdTarget {
  std::int64_t bits = 0;  // Highway's target bit (HWY_AVX2, HWY_AVX3, ...)
  std::string name;       // Highway's name: "AVX3" is AVX-512 (F, VL, DQ, BW), "AVX2" is AVX2 + FMA, ...
  bool runs_here = false; // this CPU has the instructions
};

// Every target compiled into this build, best first.
std::vector<SimdTarget> compiled_simd_targets();

// The target the dispatched kernels run on now (the best one this CPU runs, unless a ScopedSimdTarget holds).
SimdTarget dispatched_simd_target();

// FP64 lanes of one vector of `dispatched_simd_target()` (8 for AVX-512, 4 for AVX2, 2 for SSE).
int dispatched_f64_lanes();

// Makes every dispatched kernel run on `target` (which must run here: UnsupportedError otherwise) until
// destroyed; then dispatch returns to the best target. Not thread-safe: for tests and benchmarks, set
// outside parallel regions.
class ScopedSimdTarget {
 public:
  explicit ScopedSimdTarget(const SimdTarget& target);
  ~ScopedSimdTarget();
  ScopedSimdTarget(const ScopedSimdTarget&) = delete;
  ScopedSimdTarget& operator=(const ScopedSimdTarget&) = delete;
};

}  // namespace icobrdf
