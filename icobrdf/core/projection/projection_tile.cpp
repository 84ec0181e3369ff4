// Compiled once per SIMD target (Highway foreach_target); see icobrdf/core/projection/projection_tile.hpp.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "icobrdf/core/projection/projection_tile.cpp"
#include <hwy/foreach_target.h>  // re-includes this file once per target
#include <hwy/cache_control.h>
#include <hwy/highway.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/projection/projection_tile.hpp"
#include <string>

HWY_BEFORE_NAMESPACE();
namespace icobrdf {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Modes and LUT columns per register tile.
#if HWY_TARGET <= HWY_AVX3
// 32 vector registers: 25 accumulators, 5 P vectors and 1 F vector. Measured against 3 modes x 8 columns
// (Zen 4, level 5, order 8, 2 threads, alternated in one process, 2026-11-28): 1-4% faster (F is read from L1
// 9 times per chunk instead of 15, and 10 loads feed 25 FMAs instead of 11 feeding 24).
constexpr int kTileModes = 5, kTileColumns = 5;
#else
// 16 vector registers: 12 accumulators, 3 P vectors and 1 F vector.
constexpr int kTileModes = 3, kTileColumns = 4;
#endif
// Cells per chunk and LUT columns per sweep over the cells (icobrdf/core/projection/projection_tile.hpp: what stays in
// which cache). Measured on AVX-512 (Zen 5, CPU time of one thread, 2026-11-24): chunks of 128-256 cells beat
// 512 and 1024 by 5-15%; sweeps of the whole 512-column block beat 64 and 128 columns by 2-5%. With F read in
// place (Zen 4, 2026-11-27) chunks of 128, 256 and 512 cells were within the host's noise of each other.
constexpr std::ptrdiff_t kChunkCells = 256, kSweepColumns = 512;
// Bytes of packed P per block of cells: a block is the most whole chunks whose P fits this (at least one
// chunk), 1024 cells at order 8. Measured (Intel AVX-512, 2 MiB L2, 2 threads, F from memory, 20 blocks of
// 512 columns at level 5, order 8, 2026-11-27): blocks of 1024 cells took 109-117 ms against 128-154 ms for
// 256 (one chunk per block: the loop before), 110-145 for 2048, 120-156 for 4096 and 137-178 for all cells.
// The P of 1024 cells at order 8 stays in a 1 MiB L2 (Zen 5) too.
constexpr std::ptrdiff_t kBlockBytes = 384 * 1024;
// F's cache lines per prefetch address: one 64-byte line holds 8 doubles.
constexpr std::ptrdiff_t kLineDoubles = 8;
double* aligned_start(double* p) {
  while (reinterpret_cast<std::uintptr_t>(p) % kPackAlignBytes != 0) ++p;
  return p;
}

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

// acc[(q * kTileModes + r) * L + lane] += sum over the vectors kk < vectors of p[(kk * M + r) * L + lane]
// f[q ld + kk L + lane] for the M <= kTileModes modes of a group: P packed so that one step reads its M
// vectors consecutively; F's N columns read in place (stride ld). The chunk of F columns stays in L1 for the
// mode groups after the first. (Copying each chunk of F into a packed buffer first, as this tile did before,
// cost 7-10%: Zen 4, 2026-11-27.) Step kk also prefetches line kk of `pf` (one column of the chunk the tile
// reads next, or into L2 only a column of the chunk after it: `to_l2`) while kk < pf_vectors: one prefetch
// among the step's FMAs. (Issuing a chunk's prefetches in a burst before each group stalled on the
// outstanding misses: 7% of the tile's samples in `perf`, and 2-4% of its time, Zen 4, 2026-11-28.)
template <int N, int M>
HWY_INLINE void dot_tile(const double* HWY_RESTRICT p, const double* HWY_RESTRICT f, std::ptrdiff_t ld, std::ptrdiff_t vectors,
                         double* HWY_RESTRICT acc, const double* pf, std::ptrdiff_t pf_vectors, bool to_l2) {
  const hn::ScalableTag<double> d;
  const std::ptrdiff_t lanes = static_cast<std::ptrdiff_t>(hn::Lanes(d));
  using V = hn::Vec<decltype(d)>;
  V c[N][M];
  const double* col[N];
#pragma GCC unroll 16
  for (int q = 0; q < N; ++q) col[q] = f + q * ld;
#pragma GCC unroll 16
  for (int q = 0; q < N; ++q)
#pragma GCC unroll 16
    for (int r = 0; r < M; ++r) c[q][r] = hn::LoadU(d, acc + (q * kTileModes + r) * lanes);
  for (std::ptrdiff_t kk = 0; kk < vectors; ++kk, p += M * lanes) {
    if (kk < pf_vectors && (kk * lanes) % kLineDoubles == 0) {
      if (to_l2)
        __builtin_prefetch(pf + kk * lanes, 0, 2);  // locality 2: into L2 (x86 prefetcht1)
      else
        hwy::Prefetch(pf + kk * lanes);
    }
    V x[M];
#pragma GCC unroll 16
    for (int r = 0; r < M; ++r) x[r] = hn::Load(d, p + r * lanes);
#pragma GCC unroll 16
    for (int q = 0; q < N; ++q) {
      V y = hn::LoadU(d, col[q] + kk * lanes);
      keep_in_register(y);
#pragma GCC unroll 16
      for (int r = 0; r < M; ++r) c[q][r] = hn::MulAdd(x[r], y, c[q][r]);
    }
  }
#pragma GCC unroll 16
  for (int q = 0; q < N; ++q)
#pragma GCC unroll 16
    for (int r = 0; r < M; ++r) hn::StoreU(c[q][r], d, acc + (q * kTileModes + r) * lanes);
}

// dot_tile for a group of m modes, 1 <= m <= kTileModes (only the last group has fewer than kTileModes).
template <int N, int M = kTileModes>
HWY_INLINE void dot_tile_modes(std::ptrdiff_t m, const double* HWY_RESTRICT p, const double* HWY_RESTRICT f, std::ptrdiff_t ld,
                               std::ptrdiff_t vectors, double* HWY_RESTRICT acc, const double* pf, std::ptrdiff_t pf_vectors,
                               bool to_l2) {
  if constexpr (M > 1) {
    if (m < M) return dot_tile_modes<N, M - 1>(m, p, f, ld, vectors, acc, pf, pf_vectors, to_l2);
  }
  dot_tile<N, M>(p, f, ld, vectors, acc, pf, pf_vectors, to_l2);
}

// Copies columns first .. first + n - 1 (stride ld) of cells [0, vectors L) to out[(kk * n + q) * L + lane].
void pack_columns(const double* src, std::ptrdiff_t ld, std::ptrdiff_t first, std::ptrdiff_t n, std::ptrdiff_t vectors,
                  std::ptrdiff_t lanes, double* HWY_RESTRICT out) {
  for (std::ptrdiff_t q = 0; q < n; ++q) {
    const double* col = src + (first + q) * ld;
    for (std::ptrdiff_t kk = 0; kk < vectors; ++kk)
      for (std::ptrdiff_t l = 0; l < lanes; ++l) out[(kk * n + q) * lanes + l] = col[kk * lanes + l];
  }
}

std::ptrdiff_t TileLanes() { return static_cast<std::ptrdiff_t>(hn::Lanes(hn::ScalableTag<double>())); }
std::ptrdiff_t TileModes() { return kTileModes; }

// Modes of group g: kTileModes, fewer for the last group.
std::ptrdiff_t group_modes(std::ptrdiff_t g, std::ptrdiff_t modes) { return std::min<std::ptrdiff_t>(kTileModes, modes - g * kTileModes); }

// out[g M cv + (kk m + r) L + lane] = P(kk L + lane, g M + r) for the cv = cells / L * L vector cells, with M
// = kTileModes and m = group_modes(g): modes x cv values in all.
void PackProjection(const double* p, std::ptrdiff_t cells, std::ptrdiff_t modes, double* out) {
  const std::ptrdiff_t lanes = TileLanes(), cv = cells / lanes * lanes;
  const std::ptrdiff_t groups = (modes + kTileModes - 1) / kTileModes;
  for (std::ptrdiff_t g = 0; g < groups; ++g)
    pack_columns(p, cells, g * kTileModes, group_modes(g, modes), cv / lanes, lanes, out + g * kTileModes * cv);
}

void ProjectionTile(const double* packed_p, const double* p, std::ptrdiff_t cells, std::ptrdiff_t modes, const double* f,
                    std::ptrdiff_t ldf, std::ptrdiff_t w, std::ptrdiff_t k_begin, std::ptrdiff_t k_end, double* t,
                    std::vector<double>& scratch) {
  const std::ptrdiff_t lanes = TileLanes();
  const std::ptrdiff_t groups = (modes + kTileModes - 1) / kTileModes;
  const std::ptrdiff_t packed_cells = cells / lanes * lanes;  // cells of each packed mode group
  const std::ptrdiff_t cv = k_begin + (k_end - k_begin) / lanes * lanes;  // cells handled by vectors
  const std::ptrdiff_t per_column = kTileModes * lanes;  // accumulator doubles of one (mode group, column)
  const std::ptrdiff_t p_chunk_bytes = groups * kTileModes * kChunkCells * static_cast<std::ptrdiff_t>(sizeof(double));
  const std::ptrdiff_t block_cells = std::max<std::ptrdiff_t>(1, kBlockBytes / p_chunk_bytes) * kChunkCells;
  const std::ptrdiff_t acc_size = groups * kSweepColumns * per_column;
  // The accumulators of one sweep, aligned.
  scratch.resize(static_cast<size_t>(acc_size) + kPackAlignBytes / sizeof(double));
  double* acc = aligned_start(scratch.data());
  for (std::ptrdiff_t s0 = 0; s0 < w; s0 += kSweepColumns) {
    const std::ptrdiff_t sw = std::min(kSweepColumns, w - s0), swv = sw / kTileColumns * kTileColumns;
    // LUT columns of the tile starting at sweep column j: a whole tile, or one column past the last whole one.
    const auto tile_columns = [&](std::ptrdiff_t j) { return j < swv ? std::ptrdiff_t{kTileColumns} : std::ptrdiff_t{1}; };
    // A chunk of F, and the chunk the tile reads after it in the loops' order: the next chunk of the same
    // columns, else the next tile's first chunk of the block, else the next block's first; none past the sweep.
    struct Chunk {
      std::ptrdiff_t j, k, begin, end;  // first column, first cell, the block's cells [begin, end)
    };
    const auto after = [&](const Chunk& c) {
      Chunk d{c.j, c.k + kChunkCells, c.begin, c.end};
      if (d.k >= c.end) {
        d.j = c.j + tile_columns(c.j), d.k = c.begin;
        if (d.j >= sw) d = {0, c.end, c.end, std::min(cv, c.end + block_cells)};
      }
      return d;
    };
    const auto cells_of = [&](const Chunk& c) { return std::max<std::ptrdiff_t>(0, std::min(c.end, c.k + kChunkCells) - c.k); };
    const auto column_of = [&](const Chunk& c, std::ptrdiff_t q) { return f + std::min(s0 + c.j + q, w - 1) * ldf + c.k; };
    std::fill(acc, acc + groups * sw * per_column, 0.0);
    for (std::ptrdiff_t kb = k_begin; kb < cv; kb += block_cells) {
      const std::ptrdiff_t kb_end = std::min(cv, kb + block_cells);
      for (std::ptrdiff_t j0 = 0; j0 < sw;) {
        const std::ptrdiff_t n = tile_columns(j0);
        for (std::ptrdiff_t k0 = kb; k0 < kb_end; k0 += kChunkCells) {
          const std::ptrdiff_t vectors = (std::min(kb_end, k0 + kChunkCells) - k0) / lanes;
          const Chunk next = after({j0, k0, kb, kb_end}), second = after(next);
          const std::ptrdiff_t next_n = tile_columns(next.j), next_cells = cells_of(next), second_cells = cells_of(second);
          // While this chunk's groups run, group g < next_n prefetches column g of the next chunk into L1, and
          // the groups after them the columns of the chunk after that into L2, a line per step of their
          // tiles (with 9 groups of 5 columns, 4 of its 5 columns; the fifth comes from memory into L1 a
          // chunk ahead, as all did before). Measured (Zen 4, level 5, order 8, 2 threads, 2026-11-28): the
          // L2 prefetch gained 1.3-3.5% in 4 alternated runs. With fewer groups than columns (few modes)
          // the first group prefetches the next chunk's lines at once instead.
          const bool per_group = groups >= next_n;
          for (std::ptrdiff_t g = 0; g < groups; ++g) {
            if (!per_group && g == 0)
              for (std::ptrdiff_t q = 0; q < next_n; ++q)
                for (std::ptrdiff_t l = 0; l < next_cells; l += kLineDoubles) hwy::Prefetch(column_of(next, q) + l);
            const double* pf = column_of(next, std::min(g, next_n - 1));
            std::ptrdiff_t pf_vectors = per_group && g < next_n ? (next_cells + lanes - 1) / lanes : 0;
            const bool to_l2 = per_group && g >= next_n && g - next_n < tile_columns(second.j) && second_cells > 0;
            if (to_l2) pf = column_of(second, g - next_n), pf_vectors = (second_cells + lanes - 1) / lanes;
            const std::ptrdiff_t m = group_modes(g, modes);
            const double* pg = packed_p + g * kTileModes * packed_cells + k0 * m;
            double* a = acc + (g * sw + j0) * per_column;
            const double* fj = f + (s0 + j0) * ldf + k0;
            if (n == kTileColumns)
              dot_tile_modes<kTileColumns>(m, pg, fj, ldf, vectors, a, pf, pf_vectors, to_l2);
            else
              dot_tile_modes<1>(m, pg, fj, ldf, vectors, a, pf, pf_vectors, to_l2);
            if (!to_l2)
              for (std::ptrdiff_t l = vectors * lanes; l < pf_vectors * lanes; l += kLineDoubles) hwy::Prefetch(pf + l);  // beyond a short chunk
          }
        }
        j0 += n;
      }
    }
    for (std::ptrdiff_t g = 0; g < groups; ++g)
      for (std::ptrdiff_t j = 0; j < sw; ++j)
        for (std::ptrdiff_t r = 0; r < kTileModes; ++r) {
          const std::ptrdiff_t m = g * kTileModes + r;
          if (m >= modes) continue;
          double* v = acc + (g * sw + j) * per_column + r * lanes;
          for (std::ptrdiff_t step = 1; step < lanes; step *= 2)  // the lanes, pairwise
            for (std::ptrdiff_t i = 0; i + step < lanes; i += 2 * step) v[i] += v[i + step];
          double sum = v[0];
          for (std::ptrdiff_t k = cv; k < k_end; ++k) sum += p[m * cells + k] * f[(s0 + j) * ldf + k];  // the last cells
          t[(s0 + j) * modes + m] = sum;
        }
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace icobrdf
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace icobrdf {

HWY_EXPORT(TileLanes);
HWY_EXPORT(TileModes);
HWY_EXPORT(PackProjection);
HWY_EXPORT(ProjectionTile);

PackedProjection pack_projection(const Eigen::MatrixXd& p) {
  PackedProjection packed;
  packed.cells = p.rows();
  packed.modes = p.cols();
  packed.lanes = HWY_DYNAMIC_DISPATCH(TileLanes)();
  packed.group_modes = HWY_DYNAMIC_DISPATCH(TileModes)();
  const Eigen::Index cv = packed.cells / packed.lanes * packed.lanes;
  packed.storage.assign(static_cast<size_t>(packed.modes * cv) + kPackAlignBytes / sizeof(double), 0.0);
  while (reinterpret_cast<std::uintptr_t>(packed.storage.data() + packed.offset) % kPackAlignBytes != 0) ++packed.offset;
  if (packed.modes > 0) HWY_DYNAMIC_DISPATCH(PackProjection)(p.data(), p.rows(), p.cols(), packed.storage.data() + packed.offset);
  return packed;
}

void projection_tile(const PackedProjection& packed, const Eigen::MatrixXd& p, const double* f, Eigen::Index ldf, Eigen::Index w,
                     Eigen::MatrixXd& t, std::vector<double>& scratch, Eigen::Index first_cell, Eigen::Index end_cell) {
  if (end_cell < 0) end_cell = p.rows();
  const Eigen::Index lanes = HWY_DYNAMIC_DISPATCH(TileLanes)(), group_modes = HWY_DYNAMIC_DISPATCH(TileModes)();
  if (packed.lanes != lanes || packed.group_modes != group_modes || packed.cells != p.rows() || packed.modes != p.cols())
    throw ArgumentError("projection: P was packed for " + std::to_string(packed.lanes) + " lanes, groups of " + std::to_string(packed.group_modes) +
                        " modes and " + std::to_string(packed.cells) + " x " + std::to_string(packed.modes) + ", used with " + std::to_string(lanes) +
                        " lanes, groups of " + std::to_string(group_modes) + " modes and " + std::to_string(p.rows()) + " x " + std::to_string(p.cols()));
  const bool aligned_end = end_cell == p.rows() || end_cell % packed.lanes == 0;
  if (first_cell < 0 || first_cell > end_cell || end_cell > p.rows() || first_cell % packed.lanes != 0 || !aligned_end)
    throw ArgumentError("projection: cell range [" + std::to_string(first_cell) + ", " + std::to_string(end_cell) + ") of " +
                        std::to_string(p.rows()) + " cells does not start and end on a multiple of " + std::to_string(packed.lanes));
  t.resize(p.cols(), w);
  if (p.cols() == 0) return;
  HWY_DYNAMIC_DISPATCH(ProjectionTile)(packed.data(), p.data(), p.rows(), p.cols(), f, ldf, w, first_cell, end_cell, t.data(), scratch);
}

}  // namespace icobrdf
#endif
