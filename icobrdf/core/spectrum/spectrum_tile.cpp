// Compiled once per SIMD target (Highway foreach_target); see icobrdf/core/spectrum/spectrum_tile.hpp.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "icobrdf/core/spectrum/spectrum_tile.cpp"
#include <hwy/foreach_target.h>  // re-includes this file once per target
#include <hwy/highway.h>

#include <cstddef>

#include "icobrdf/core/spectrum/spectrum_tile.hpp"

HWY_BEFORE_NAMESPACE();
namespace icobrdf {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

#if HWY_TARGET <= HWY_AVX3
// 32 vector registers: V Cols accumulators + V K_i vectors + 1 broadcast <= 31 for V = 3, Cols <= 9.
constexpr int kTileVectors = 3, kMinCols = 4, kMaxCols = 9;
#else
// 16 vector registers: V Cols + V + 1 <= 15 for V = 2, Cols <= 6.
constexpr int kTileVectors = 2, kMinCols = 4, kMaxCols = 6;
#endif

std::ptrdiff_t SpectrumLanes() { return static_cast<std::ptrdiff_t>(hn::Lanes(hn::ScalableTag<double>())); }
std::ptrdiff_t SpectrumPairs() { return kTileVectors * SpectrumLanes(); }

// The panel width that pads m least (ties: the wider one, fewer passes over K_i).
int SpectrumCols(int m) {
  int best = kMaxCols;
  for (int c = kMaxCols - 1; c >= kMinCols; --c)
    if ((m + c - 1) / c * c < (m + best - 1) / best * best) best = c;
  return best;
}

// Dense path, one width: packed holds panel b, row k, column jj at (b m + k) Cols + jj.
// For each register tile of V L pairs from p0 = 0: body(p0, fv) adds the tile's values into fv[V], which are
// then stored to f[p0 ..].
template <class Body>
HWY_INLINE void ForPairTiles(std::ptrdiff_t np, double* HWY_RESTRICT f, const Body& body) {
  const hn::ScalableTag<double> d;
  const std::ptrdiff_t lanes = static_cast<std::ptrdiff_t>(hn::Lanes(d));
  for (std::ptrdiff_t p0 = 0; p0 < np; p0 += kTileVectors * lanes) {
    hn::Vec<decltype(d)> fv[kTileVectors];
#pragma GCC unroll 4
    for (int v = 0; v < kTileVectors; ++v) fv[v] = hn::Zero(d);
    body(p0, fv);
#pragma GCC unroll 4
    for (int v = 0; v < kTileVectors; ++v) hn::StoreU(fv[v], d, f + p0 + v * lanes);
  }
}

// Dense path, one width: packed holds panel b, row k, column jj at (b m + k) Cols + jj.
template <int Cols>
void DenseTiles(int m, int panels, std::ptrdiff_t np, const double* HWY_RESTRICT ki, const double* HWY_RESTRICT kr, std::ptrdiff_t ld,
                const double* HWY_RESTRICT packed, double* HWY_RESTRICT f) {
  const hn::ScalableTag<double> d;
  using Vec = hn::Vec<decltype(d)>;
  constexpr int V = kTileVectors;
  const std::ptrdiff_t lanes = static_cast<std::ptrdiff_t>(hn::Lanes(d));
  ForPairTiles(np, f, [&](std::ptrdiff_t p0, Vec* fv) {
    for (int b = 0; b < panels; ++b) {
      Vec acc[V][Cols];
#pragma GCC unroll 4
      for (int v = 0; v < V; ++v)
#pragma GCC unroll 16
        for (int jj = 0; jj < Cols; ++jj) acc[v][jj] = hn::Zero(d);
      const double* HWY_RESTRICT cp = packed + static_cast<std::ptrdiff_t>(b) * m * Cols;
      const double* HWY_RESTRICT x = ki + p0;
      for (int k = 0; k < m; ++k, x += ld, cp += Cols) {
        Vec xv[V];
#pragma GCC unroll 4
        for (int v = 0; v < V; ++v) xv[v] = hn::LoadU(d, x + v * lanes);
#pragma GCC unroll 16
        for (int jj = 0; jj < Cols; ++jj) {
          const Vec cb = hn::Set(d, cp[jj]);
#pragma GCC unroll 4
          for (int v = 0; v < V; ++v) acc[v][jj] = hn::MulAdd(xv[v], cb, acc[v][jj]);
        }
      }
      const double* HWY_RESTRICT y = kr + static_cast<std::ptrdiff_t>(b) * Cols * ld + p0;
#pragma GCC unroll 16
      for (int jj = 0; jj < Cols; ++jj, y += ld)
#pragma GCC unroll 4
        for (int v = 0; v < V; ++v) fv[v] = hn::MulAdd(acc[v][jj], hn::LoadU(d, y + v * lanes), fv[v]);
    }
  });
}

template <int Cols>
void DenseIfCols(int cols, int m, int panels, std::ptrdiff_t np, const double* ki, const double* kr, std::ptrdiff_t ld, const double* packed,
                 double* f) {
  if constexpr (Cols <= kMaxCols) {
    if (cols == Cols) return DenseTiles<Cols>(m, panels, np, ki, kr, ld, packed, f);
    DenseIfCols<Cols + 1>(cols, m, panels, np, ki, kr, ld, packed, f);
  }
}

void DenseSpectrum(int cols, int m, int panels, std::ptrdiff_t np, const double* ki, const double* kr, std::ptrdiff_t ld, const double* packed,
                   double* f) {
  DenseIfCols<kMinCols>(cols, m, panels, np, ki, kr, ld, packed, f);
}

// Sparse path: group g's block C(S, S) (s x s, S = index[start[g] .. start[g + 1])) at consecutive
// offsets, column after column: packed[off + bi s + ai] = C(S[ai], S[bi]).
void SparseSpectrum(int groups, const int* start, const int* index, std::ptrdiff_t np, const double* HWY_RESTRICT ki,
                    const double* HWY_RESTRICT kr, std::ptrdiff_t ld, const double* HWY_RESTRICT packed, double* HWY_RESTRICT f) {
  const hn::ScalableTag<double> d;
  using Vec = hn::Vec<decltype(d)>;
  constexpr int V = kTileVectors;
  const std::ptrdiff_t lanes = static_cast<std::ptrdiff_t>(hn::Lanes(d));
  ForPairTiles(np, f, [&](std::ptrdiff_t p0, Vec* fv) {
    const double* HWY_RESTRICT cp = packed;
    for (int g = 0; g < groups; ++g) {
      const int* s = index + start[g];
      const int n = start[g + 1] - start[g];
      for (int bi = 0; bi < n; ++bi) {
        Vec acc[V];
#pragma GCC unroll 4
        for (int v = 0; v < V; ++v) acc[v] = hn::Zero(d);
        for (int ai = 0; ai < n; ++ai, ++cp) {
          const Vec cb = hn::Set(d, *cp);
          const double* x = ki + static_cast<std::ptrdiff_t>(s[ai]) * ld + p0;
#pragma GCC unroll 4
          for (int v = 0; v < V; ++v) acc[v] = hn::MulAdd(hn::LoadU(d, x + v * lanes), cb, acc[v]);
        }
        const double* y = kr + static_cast<std::ptrdiff_t>(s[bi]) * ld + p0;
#pragma GCC unroll 4
        for (int v = 0; v < V; ++v) fv[v] = hn::MulAdd(acc[v], hn::LoadU(d, y + v * lanes), fv[v]);
      }
    }
  });
}

}  // namespace HWY_NAMESPACE
}  // namespace icobrdf
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <cmath>
#include <string>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"

namespace icobrdf {

HWY_EXPORT(SpectrumLanes);
HWY_EXPORT(SpectrumPairs);
HWY_EXPORT(SpectrumCols);
HWY_EXPORT(DenseSpectrum);
HWY_EXPORT(SparseSpectrum);

PackedSpectrum pack_spectrum(const Eigen::MatrixXd& c, int order, bool allow_sparse) {
  PackedSpectrum p;
  p.m = hemisphere_basis_count(order);
  if (c.rows() != p.m || c.cols() != p.m)
    throw ArgumentError("spectrum tile: C is " + std::to_string(c.rows()) + " x " + std::to_string(c.cols()) + ", expected " +
                        std::to_string(p.m) + " x " + std::to_string(p.m) + " for order " + std::to_string(order));
  p.lanes = HWY_DYNAMIC_DISPATCH(SpectrumLanes)();
  p.tile_pairs = HWY_DYNAMIC_DISPATCH(SpectrumPairs)();
  std::vector<int> l_of(static_cast<size_t>(p.m));
  for (int j = 0; j < p.m; ++j) l_of[static_cast<size_t>(j)] = ansi_to_nl(j).l;
  bool block_diagonal = allow_sparse;
  for (int b = 0; b < p.m && block_diagonal; ++b)
    for (int a = 0; a < p.m; ++a)
      if (l_of[static_cast<size_t>(a)] != l_of[static_cast<size_t>(b)] && c(a, b) != 0.0) {
        block_diagonal = false;
        break;
      }
  if (block_diagonal) {
    p.sparse = true;
    // Isotropic: the block of -l equals that of l, entry by entry.
    p.isotropic = true;
    for (int l = 1; l <= order && p.isotropic; ++l)
      for (int n = l; n <= order && p.isotropic; n += 2)
        for (int k = l; k <= order; k += 2)
          if (c(ansi_index(n, l), ansi_index(k, l)) != c(ansi_index(n, -l), ansi_index(k, -l))) {
            p.isotropic = false;
            break;
          }
    if (p.isotropic)
      for (int l = 0; l <= order; ++l)
        for (int k = l; k <= order; k += 2)
          for (int n = l; n <= order; n += 2)
            p.radial_blocks.push_back(c(ansi_index(n, l), ansi_index(k, l)) * std::sqrt((n + 1) / M_PI) * std::sqrt((k + 1) / M_PI) *
                                      (l == 0 ? 0.5 : 1.0));
    p.group_start.push_back(0);
    for (int l = -order; l <= order; ++l) {
      for (int j = 0; j < p.m; ++j)
        if (l_of[static_cast<size_t>(j)] == l) p.group_index.push_back(j);
      p.group_start.push_back(static_cast<int>(p.group_index.size()));
    }
    for (size_t g = 0; g + 1 < p.group_start.size(); ++g) {
      const int* s = p.group_index.data() + p.group_start[g];
      const int n = p.group_start[g + 1] - p.group_start[g];
      for (int bi = 0; bi < n; ++bi)
        for (int ai = 0; ai < n; ++ai) p.storage.push_back(c(s[ai], s[bi]));
    }
    return p;
  }
  p.cols = HWY_DYNAMIC_DISPATCH(SpectrumCols)(p.m);
  p.panels = (p.m + p.cols - 1) / p.cols;
  p.storage.assign(static_cast<size_t>(p.panels) * p.m * p.cols, 0.0);
  for (int b = 0; b < p.panels; ++b)
    for (int k = 0; k < p.m; ++k)
      for (int jj = 0; jj < p.cols && b * p.cols + jj < p.m; ++jj)
        p.storage[(static_cast<size_t>(b) * p.m + k) * p.cols + jj] = c(k, b * p.cols + jj);
  return p;
}

Eigen::Index spectrum_tile_columns(const PackedSpectrum& packed) {
  return packed.sparse ? packed.m : static_cast<Eigen::Index>(packed.panels) * packed.cols;
}

void spectrum_tile(const PackedSpectrum& packed, Eigen::Index np, const double* ki, const double* kr, Eigen::Index ld, double* f) {
  if (packed.lanes != HWY_DYNAMIC_DISPATCH(SpectrumLanes)())
    throw ArgumentError("spectrum tile: C was packed for " + std::to_string(packed.lanes) + " lanes, used with " +
                        std::to_string(HWY_DYNAMIC_DISPATCH(SpectrumLanes)()));
  const Eigen::Index rounded = (np + packed.tile_pairs - 1) / packed.tile_pairs * packed.tile_pairs;
  if (ld < rounded)
    throw ArgumentError("spectrum tile: leading dimension " + std::to_string(ld) + " is shorter than the " + std::to_string(rounded) +
                        " rows of " + std::to_string(np) + " pairs rounded up to the tile");
  if (np <= 0) return;
  if (packed.sparse)
    HWY_DYNAMIC_DISPATCH(SparseSpectrum)(static_cast<int>(packed.group_start.size()) - 1, packed.group_start.data(),
                                         packed.group_index.data(), rounded, ki, kr, ld, packed.storage.data(), f);
  else
    HWY_DYNAMIC_DISPATCH(DenseSpectrum)(packed.cols, packed.m, packed.panels, rounded, ki, kr, ld, packed.storage.data(), f);
}

}  // namespace icobrdf
#endif
