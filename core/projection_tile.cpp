// Compiled once per SIMD target (Highway foreach_target); see core/projection_tile.hpp.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/projection_tile.cpp"
#include <hwy/foreach_target.h>  // re-includes this file once per target
#include <hwy/highway.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "core/projection_tile.hpp"

HWY_BEFORE_NAMESPACE();
namespace icobrdf {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Modes per register tile.
constexpr int kTileModes = 3;
#if HWY_TARGET <= HWY_AVX3
// 32 vector registers: 24 accumulators, 3 P vectors and 1 F vector.
constexpr int kTileColumns = 8;
#else
// 16 vector registers: 12 accumulators, 3 P vectors and 1 F vector.
constexpr int kTileColumns = 4;
#endif
// Cells per chunk: the chunk of P (45 modes x 512 cells = 184 KB at order 8) stays in L2 (chunks of 128 to
// 1024 cells measured on AVX2 and AVX-512: 512 was fastest or within noise).
constexpr std::ptrdiff_t kChunkCells = 512;

// Keeps a loaded vector in a register: without this, GCC folds the load of F into each of the 3 FMAs that
// use it (3 loads instead of 1), and the load ports saturate before the FMA pipes.
template <class V>
HWY_INLINE void keep_in_register(V& v) {
#if HWY_ARCH_X86 && (HWY_TARGET <= HWY_AVX3) && defined(__GNUC__)
  asm("" : "+v"(v.raw));
#elif HWY_ARCH_X86 && (HWY_TARGET <= HWY_SSSE3) && defined(__GNUC__)
  asm("" : "+x"(v.raw));
#else
  (void)v;
#endif
}

// acc[(q * M + r) * L + lane] += sum over the vectors kk < vectors of p[(kk * M + r) * L + lane] f[(kk * N + q) * L + lane]:
// P and F packed so that one step of the loop reads M + N consecutive vectors (two pointers, no spills).
template <int N>
HWY_INLINE void dot_tile(const double* HWY_RESTRICT p, const double* HWY_RESTRICT f, std::ptrdiff_t vectors, double* HWY_RESTRICT acc) {
  const hn::ScalableTag<double> d;
  const std::ptrdiff_t lanes = static_cast<std::ptrdiff_t>(hn::Lanes(d));
  using V = hn::Vec<decltype(d)>;
  V c[N][kTileModes];
#pragma GCC unroll 16
  for (int q = 0; q < N; ++q)
#pragma GCC unroll 16
    for (int r = 0; r < kTileModes; ++r) c[q][r] = hn::LoadU(d, acc + (q * kTileModes + r) * lanes);
  for (std::ptrdiff_t kk = 0; kk < vectors; ++kk, p += kTileModes * lanes, f += N * lanes) {
    V x[kTileModes];
#pragma GCC unroll 16
    for (int r = 0; r < kTileModes; ++r) x[r] = hn::Load(d, p + r * lanes);
#pragma GCC unroll 16
    for (int q = 0; q < N; ++q) {
      V y = hn::Load(d, f + q * lanes);
      keep_in_register(y);
#pragma GCC unroll 16
      for (int r = 0; r < kTileModes; ++r) c[q][r] = hn::MulAdd(x[r], y, c[q][r]);
    }
  }
#pragma GCC unroll 16
  for (int q = 0; q < N; ++q)
#pragma GCC unroll 16
    for (int r = 0; r < kTileModes; ++r) hn::StoreU(c[q][r], d, acc + (q * kTileModes + r) * lanes);
}

// Copies `n` columns (stride ld) of cells [k0, k0 + vectors L) to out[(kk * n + q) * L + lane]; a column
// index beyond `last` repeats column `last`.
void pack_columns(const double* src, std::ptrdiff_t ld, std::ptrdiff_t first, std::ptrdiff_t n, std::ptrdiff_t last, std::ptrdiff_t k0,
                  std::ptrdiff_t vectors, std::ptrdiff_t lanes, double* HWY_RESTRICT out) {
  for (std::ptrdiff_t q = 0; q < n; ++q) {
    const double* col = src + std::min(first + q, last) * ld + k0;
    for (std::ptrdiff_t kk = 0; kk < vectors; ++kk)
      for (std::ptrdiff_t l = 0; l < lanes; ++l) out[(kk * n + q) * lanes + l] = col[kk * lanes + l];
  }
}

void ProjectionTile(const double* p, std::ptrdiff_t cells, std::ptrdiff_t modes, const double* f, std::ptrdiff_t ldf, std::ptrdiff_t w,
                    double* t, std::vector<double>& scratch) {
  const hn::ScalableTag<double> d;
  const std::ptrdiff_t lanes = static_cast<std::ptrdiff_t>(hn::Lanes(d));
  const std::ptrdiff_t groups = (modes + kTileModes - 1) / kTileModes, wv = w / kTileColumns * kTileColumns;
  const std::ptrdiff_t cv = cells / lanes * lanes;  // cells handled by vectors
  const std::ptrdiff_t per_column = kTileModes * lanes;  // accumulator doubles of one (mode group, column)
  const std::ptrdiff_t acc_size = groups * w * per_column, pack_p_size = groups * kTileModes * kChunkCells,
                       pack_f_size = kTileColumns * kChunkCells;
  // One buffer: accumulators, then the packed chunk of P, then the packed chunk of F's columns; each part
  // starts on a whole number of vectors (the packed loads are aligned).
  constexpr std::uintptr_t kAlignBytes = 64;  // the widest vector of any target
  scratch.assign(static_cast<size_t>(acc_size + pack_p_size + pack_f_size) + kAlignBytes / sizeof(double), 0.0);
  double* acc = scratch.data();
  double* base = acc + acc_size;
  while (reinterpret_cast<std::uintptr_t>(base) % kAlignBytes != 0) ++base;
  double* pack_p = base;
  double* pack_f = pack_p + pack_p_size;
  for (std::ptrdiff_t k0 = 0; k0 < cv; k0 += kChunkCells) {
    const std::ptrdiff_t vectors = (std::min(cv, k0 + kChunkCells) - k0) / lanes;
    // A short last mode group repeats the last mode; its sums are never read.
    for (std::ptrdiff_t g = 0; g < groups; ++g)
      pack_columns(p, cells, g * kTileModes, kTileModes, modes - 1, k0, vectors, lanes, pack_p + g * kTileModes * vectors * lanes);
    for (std::ptrdiff_t j0 = 0; j0 < w;) {
      const std::ptrdiff_t n = j0 < wv ? kTileColumns : 1;
      pack_columns(f, ldf, j0, n, w - 1, k0, vectors, lanes, pack_f);
      for (std::ptrdiff_t g = 0; g < groups; ++g) {
        const double* pg = pack_p + g * kTileModes * vectors * lanes;
        double* a = acc + (g * w + j0) * per_column;
        if (n == kTileColumns)
          dot_tile<kTileColumns>(pg, pack_f, vectors, a);
        else
          dot_tile<1>(pg, pack_f, vectors, a);
      }
      j0 += n;
    }
  }
  for (std::ptrdiff_t g = 0; g < groups; ++g)
    for (std::ptrdiff_t j = 0; j < w; ++j)
      for (std::ptrdiff_t r = 0; r < kTileModes; ++r) {
        const std::ptrdiff_t m = g * kTileModes + r;
        if (m >= modes) continue;
        double* v = acc + (g * w + j) * per_column + r * lanes;
        for (std::ptrdiff_t step = 1; step < lanes; step *= 2)  // the lanes, pairwise
          for (std::ptrdiff_t i = 0; i + step < lanes; i += 2 * step) v[i] += v[i + step];
        double sum = v[0];
        for (std::ptrdiff_t k = cv; k < cells; ++k) sum += p[m * cells + k] * f[j * ldf + k];  // the last cells
        t[j * modes + m] = sum;
      }
}

}  // namespace HWY_NAMESPACE
}  // namespace icobrdf
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace icobrdf {

HWY_EXPORT(ProjectionTile);

void projection_tile(const Eigen::MatrixXd& p, const double* f, Eigen::Index ldf, Eigen::Index w, Eigen::MatrixXd& t,
                     std::vector<double>& scratch) {
  t.resize(p.cols(), w);
  HWY_DYNAMIC_DISPATCH(ProjectionTile)(p.data(), p.rows(), p.cols(), f, ldf, w, t.data(), scratch);
}

}  // namespace icobrdf
#endif
