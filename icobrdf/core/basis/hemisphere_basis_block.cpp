// Block evaluation of the hemisphere basis K_n^l with the directions innermost (icobrdf/core/basis/hemisphere_basis.hpp:
// hemisphere_basis_block, hemisphere_basis_weighted_sum), compiled once per SIMD target (Highway
// foreach_target) and dispatched at run time to the widest vectors the CPU has (icobrdf/core/support/simd_target.hpp).
//
// Directions are taken in chunks of V vectors of L lanes (L = 8 on AVX-512, 4 on AVX2; up to 32 directions
// per chunk). Every step of the recurrences (radial rows, azimuthal powers, products) is then V full vector
// operations on data that stays in L1, instead of one short loop per direction. The arithmetic is that of
// hemisphere_basis_eval: Lambert radius rho^2 = (x^2 + y^2) / (1 + z), unit azimuth (x, y) / |(x, y)|,
// cos(l phi) + i sin(l phi) by repeated complex multiplication, the Zernike rows by the Shakibaei-Paramesran
// recurrence (icobrdf/core/basis/zernike.hpp), K = (sqrt((n + 1) / pi) R) az. Only the radial rows n - 1, n - 2 are
// kept, so the workspace is O(order) per direction, not O(order^2).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "icobrdf/core/basis/hemisphere_basis_block.cpp"
#include <hwy/foreach_target.h>  // re-includes this file once per target
#include <hwy/aligned_allocator.h>
#include <hwy/highway.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstring>

#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/basis/isotropic_evaluation.hpp"
#include "icobrdf/core/basis/zernike.hpp"

#ifndef ICOBRDF_HEMISPHERE_BASIS_BLOCK_ONCE
#define ICOBRDF_HEMISPHERE_BASIS_BLOCK_ONCE
namespace icobrdf::basis_block_detail {
// Largest chunk: 32 directions (4 AVX-512 vectors, 8 AVX2 vectors).
constexpr int kChunk = 32;
// sqrt((n + 1) / pi) for n <= 128.
inline const std::array<double, kMaxZernikeOrder + 1>& norms() {
  static const std::array<double, kMaxZernikeOrder + 1> t = [] {
    std::array<double, kMaxZernikeOrder + 1> v{};
    for (int n = 0; n <= kMaxZernikeOrder; ++n) v[static_cast<size_t>(n)] = std::sqrt((n + 1) / M_PI);
    return v;
  }();
  return t;
}
// Radial rows R_n^m (m = n % 2, ..., n) of all n <= order, row after row: row n starts at radial_offset(n).
inline int radial_offset(int n) { return (n / 2) * (n / 2 + 1) + (n % 2) * (n / 2 + 1); }
inline int radial_table_size(int order) { return radial_offset(order + 1); }
}  // namespace icobrdf::basis_block_detail
#endif

HWY_BEFORE_NAMESPACE();
namespace icobrdf {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
using basis_block_detail::kChunk;
using basis_block_detail::radial_offset;
using basis_block_detail::radial_table_size;

using D = hn::ScalableTag<double>;
using Vec = hn::Vec<D>;
constexpr int kL = static_cast<int>(HWY_LANES(double));  // lanes of one vector on this target
constexpr int kMaxV = kChunk / kL;                       // vectors of the largest chunk

// Per-thread workspace (doubles, aligned): azimuthal factors (2 order + 1) chunks, three radial rows of
// (order / 2 + 1) chunks, accumulators (one vector per mode) for weighted sums, a chunk of directions and of
// outputs for partial chunks, and all radial rows of two chunks (the isotropic form).
struct Workspace {
  hwy::AlignedFreeUniquePtr<double[]> az, rows, acc, tail, dirs, radial;
  size_t az_n = 0, rows_n = 0, acc_n = 0, tail_n = 0, radial_n = 0;
};

void ensure(hwy::AlignedFreeUniquePtr<double[]>& p, size_t& have, size_t need) {
  if (have >= need) return;
  p = hwy::AllocateAligned<double>(need);
  have = need;
}

Workspace& workspace(int order) {
  thread_local Workspace ws;
  const size_t m = static_cast<size_t>((order + 1) * (order + 2) / 2);
  ensure(ws.az, ws.az_n, (2 * static_cast<size_t>(order) + 1) * kChunk);
  ensure(ws.rows, ws.rows_n, 3 * (static_cast<size_t>(order) / 2 + 1) * kChunk);
  ensure(ws.acc, ws.acc_n, m * kL);
  ensure(ws.tail, ws.tail_n, m * kChunk);
  ensure(ws.radial, ws.radial_n, 2 * static_cast<size_t>(radial_table_size(order)) * kChunk);
  if (!ws.dirs) ws.dirs = hwy::AllocateAligned<double>(4 * kChunk);
  return ws;
}

// Lane quantities of one chunk: Lambert radius, unit azimuth (c1, s1) and weight.
template <int V>
struct Chunk {
  Vec rho[V], c1[V], s1[V], w[V];
};

// Directions dirs[3 r .. 3 r + 2] for r < n (n <= V L); the remaining lanes are the pole with weight 0.
template <int V>
HWY_INLINE void prepare(const double* dirs, int n, const double* w, Workspace& ws, Chunk<V>& ch) {
  const D d;
  const double* src = dirs;
  double* ww = ws.dirs.get() + 3 * kChunk;
  if (n < V * kL) {
    double* pad = ws.dirs.get();
    std::memcpy(pad, dirs, sizeof(double) * 3 * static_cast<size_t>(n));
    for (int r = n; r < V * kL; ++r) pad[3 * r] = 0.0, pad[3 * r + 1] = 0.0, pad[3 * r + 2] = 1.0;
    src = pad;
  }
  for (int r = 0; r < V * kL; ++r) ww[r] = r >= n ? 0.0 : (w ? w[r] : 1.0);
  const Vec zero = hn::Zero(d), one = hn::Set(d, 1.0);
  for (int v = 0; v < V; ++v) {
    Vec x, y, z;
    hn::LoadInterleaved3(d, src + 3 * kL * v, x, y, z);
    ch.w[v] = hn::Load(d, ww + kL * v);
    const Vec zc = hn::Max(z, zero);  // z down to -kHorizonSlack is the horizon
    const Vec h2 = hn::MulAdd(x, x, hn::Mul(y, y));
    // rho^2 = 1 - cos(theta) = h2 / (1 + z), without cancellation (icobrdf/core/basis/lambert_map.hpp).
    const Vec r2 = hn::Div(h2, hn::Add(one, zc));
    ch.rho[v] = hn::Sqrt(hn::Min(r2, one));
    const Vec s = hn::Sqrt(h2);
    const auto pos = hn::Gt(s, zero);
    const Vec safe = hn::IfThenElse(pos, s, one);  // the pole: azimuth 0, every l != 0 vanishes there anyway
    ch.c1[v] = hn::IfThenElse(pos, hn::Div(x, safe), one);
    ch.s1[v] = hn::IfThenElse(pos, hn::Div(y, safe), zero);
  }
}

// Writes K_j of a chunk: out[j * ld + lane].
template <int V>
struct StoreSink {
  static constexpr bool kScaleRows = true;  // values times sqrt((n + 1) / pi) as they are emitted
  double* out;
  std::ptrdiff_t ld;
  HWY_INLINE void emit(int j, const Vec* rs, const double* a) const {
    const D d;
    double* o = out + static_cast<std::ptrdiff_t>(j) * ld;
    for (int v = 0; v < V; ++v) hn::StoreU(hn::Mul(rs[v], hn::Load(d, a + kL * v)), d, o + kL * v);
  }
};

// Adds sum over the chunk's vectors of R a (weights are inside a) to acc[j]; the normalization is applied at
// the end.
template <int V>
struct AccumulateSink {
  static constexpr bool kScaleRows = false;
  double* acc;
  HWY_INLINE void emit(int j, const Vec* r, const double* a) const {
    const D d;
    Vec t = hn::Mul(r[0], hn::Load(d, a));
    for (int v = 1; v < V; ++v) t = hn::MulAdd(r[v], hn::Load(d, a + kL * v), t);
    double* p = acc + static_cast<std::ptrdiff_t>(j) * kL;
    hn::Store(hn::Add(hn::Load(d, p), t), d, p);
  }
};

// The Zernike rows of a chunk, R_n^m for m = n % 2, n % 2 + 2, ..., n (entry i holds m = 2 i + n % 2, one chunk
// quantity each), by the Shakibaei-Paramesran recurrence, row after row: row_at(n) says where row n goes (rows
// n - 1 and n - 2 must still be there when row n is computed), emit_row(n, row) is called once it is complete.
template <int V, class RowAt, class EmitRow>
HWY_INLINE void radial_rows(int order, const Chunk<V>& ch, const RowAt& row_at, const EmitRow& emit_row) {
  const D d;
  constexpr int kStride = V * kL;
  for (int v = 0; v < V; ++v) hn::Store(hn::Set(d, 1.0), d, row_at(0) + kL * v);  // R_0^0
  emit_row(0, row_at(0));
  if (order == 0) return;
  for (int v = 0; v < V; ++v) hn::Store(ch.rho[v], d, row_at(1) + kL * v);  // R_1^1
  emit_row(1, row_at(1));
  const Vec two = hn::Set(d, 2.0);
  for (int n = 2; n <= order; ++n) {
    double* HWY_RESTRICT cur = row_at(n);
    const double* HWY_RESTRICT prev = row_at(n - 1);
    const double* HWY_RESTRICT prev2 = row_at(n - 2);
    const int last = n / 2;
    auto at = [&](const double* row, int i, int v) { return hn::Load(d, row + i * kStride + kL * v); };
    if (n % 2 == 0) {
      // l = 2i from l' = 2i - 1, 2i + 1 of row n - 1 (indices i - 1, i); at l = 0, |l - 1| = 1.
      for (int v = 0; v < V; ++v) hn::Store(hn::MulSub(hn::Mul(two, ch.rho[v]), at(prev, 0, v), at(prev2, 0, v)), d, cur + kL * v);
      for (int i = 1; i < last; ++i)
        for (int v = 0; v < V; ++v)
          hn::Store(hn::MulSub(ch.rho[v], hn::Add(at(prev, i - 1, v), at(prev, i, v)), at(prev2, i, v)), d, cur + i * kStride + kL * v);
      for (int v = 0; v < V; ++v) hn::Store(hn::Mul(ch.rho[v], at(prev, last - 1, v)), d, cur + last * kStride + kL * v);
    } else {
      // l = 2i + 1 from l' = 2i, 2i + 2 (indices i, i + 1).
      for (int i = 0; i < last; ++i)
        for (int v = 0; v < V; ++v)
          hn::Store(hn::MulSub(ch.rho[v], hn::Add(at(prev, i, v), at(prev, i + 1, v)), at(prev2, i, v)), d, cur + i * kStride + kL * v);
      for (int v = 0; v < V; ++v) hn::Store(hn::Mul(ch.rho[v], at(prev, last, v)), d, cur + last * kStride + kL * v);
    }
    emit_row(n, cur);
  }
}

// All K_n^l of one chunk, row n after row n of the Zernike recurrence, handed to the sink.
template <int V, bool Weighted, class Sink>
HWY_INLINE void eval_chunk(int order, const Chunk<V>& ch, Workspace& ws, const Sink& sink) {
  const D d;
  double* HWY_RESTRICT az = ws.az.get();
  constexpr int kStride = V * kL;  // doubles of one chunk quantity
  // az[(order + l) kStride + lane] = w az_l(phi): az_0 = 1/sqrt(2), az_l = cos(l phi), az_-l = sin(l phi).
  {
    Vec c[V], s[V];
    for (int v = 0; v < V; ++v) {
      hn::Store(Weighted ? hn::Mul(ch.w[v], hn::Set(d, M_SQRT1_2)) : hn::Set(d, M_SQRT1_2), d, az + order * kStride + kL * v);
      c[v] = hn::Set(d, 1.0);
      s[v] = hn::Zero(d);
    }
    for (int l = 1; l <= order; ++l)
      for (int v = 0; v < V; ++v) {
        const Vec cn = hn::MulSub(c[v], ch.c1[v], hn::Mul(s[v], ch.s1[v]));
        s[v] = hn::MulAdd(s[v], ch.c1[v], hn::Mul(c[v], ch.s1[v]));
        c[v] = cn;
        hn::Store(Weighted ? hn::Mul(ch.w[v], c[v]) : c[v], d, az + (order + l) * kStride + kL * v);
        hn::Store(Weighted ? hn::Mul(ch.w[v], s[v]) : s[v], d, az + (order - l) * kStride + kL * v);
      }
  }
  const double* centre = az + order * kStride;
  const int row_len = (order / 2 + 1) * kStride;
  double* buf[3] = {ws.rows.get(), ws.rows.get() + row_len, ws.rows.get() + 2 * row_len};
  const auto& norm = basis_block_detail::norms();
  auto emit_row = [&](int n, const double* r) {
    const int j0 = n * (n + 1) / 2, p = n % 2;
    const Vec nn = hn::Set(d, norm[static_cast<size_t>(n)]);
    for (int i = 0; i <= n / 2; ++i) {
      const int m = 2 * i + p;  // |l|
      Vec rs[V];
      for (int v = 0; v < V; ++v) {
        const Vec rv = hn::Load(d, r + i * kStride + kL * v);
        rs[v] = Sink::kScaleRows ? hn::Mul(nn, rv) : rv;
      }
      if (m == 0) {
        sink.emit(j0 + n / 2, rs, centre);
      } else {
        sink.emit(j0 + (n - m) / 2, rs, centre - m * kStride);  // l = -m
        sink.emit(j0 + (n + m) / 2, rs, centre + m * kStride);  // l = +m
      }
    }
  };
  radial_rows<V>(order, ch, [&](int n) { return buf[n % 3]; }, emit_row);
}

// n <= V L directions into out[j * ld + r]; a partial chunk goes through the tail buffer.
template <int V>
void block_chunk(int order, int n, const double* dirs, double* out, std::ptrdiff_t ld, Workspace& ws) {
  Chunk<V> ch;
  prepare<V>(dirs, n, nullptr, ws, ch);
  if (n == V * kL) {
    eval_chunk<V, false>(order, ch, ws, StoreSink<V>{out, ld});
    return;
  }
  eval_chunk<V, false>(order, ch, ws, StoreSink<V>{ws.tail.get(), V * kL});
  const int m = (order + 1) * (order + 2) / 2;
  for (int j = 0; j < m; ++j)
    std::memcpy(out + static_cast<std::ptrdiff_t>(j) * ld, ws.tail.get() + static_cast<size_t>(j) * V * kL, sizeof(double) * static_cast<size_t>(n));
}

// The isotropic form (icobrdf/core/basis/isotropic_evaluation.hpp) at n <= V L pairs: f[r] for r < n.
template <int V>
void isotropic_chunk(int order, const double* blocks, int n, const double* wi, const double* wr, Workspace& ws, double* f) {
  const D d;
  constexpr int kStride = V * kL;
  Chunk<V> ci, cr;
  prepare<V>(wi, n, nullptr, ws, ci);
  prepare<V>(wr, n, nullptr, ws, cr);
  double* ti = ws.radial.get();
  double* tr = ti + static_cast<size_t>(radial_table_size(order)) * kChunk;
  const auto none = [](int, const double*) {};
  radial_rows<V>(order, ci, [&](int nn) { return ti + radial_offset(nn) * kStride; }, none);
  radial_rows<V>(order, cr, [&](int nn) { return tr + radial_offset(nn) * kStride; }, none);
  // cos(L dphi), sin(L dphi) of dphi = phi_i - phi_r, by repeated complex multiplication.
  Vec cd[V], sd[V], cl[V], sl[V], fv[V];
  for (int v = 0; v < V; ++v) {
    cd[v] = hn::MulAdd(ci.c1[v], cr.c1[v], hn::Mul(ci.s1[v], cr.s1[v]));
    sd[v] = hn::MulSub(ci.s1[v], cr.c1[v], hn::Mul(ci.c1[v], cr.s1[v]));
    cl[v] = hn::Set(d, 1.0);
    sl[v] = hn::Zero(d);
    fv[v] = hn::Zero(d);
  }
  const double* blk = blocks;
  for (int l = 0; l <= order; ++l) {
    if (l > 0)
      for (int v = 0; v < V; ++v) {
        const Vec cn = hn::MulSub(cl[v], cd[v], hn::Mul(sl[v], sd[v]));
        sl[v] = hn::MulAdd(sl[v], cd[v], hn::Mul(cl[v], sd[v]));
        cl[v] = cn;
      }
    const int count = (order - l) / 2 + 1;
    Vec acc[V];
    for (int v = 0; v < V; ++v) acc[v] = hn::Zero(d);
    for (int b = 0; b < count; ++b) {
      Vec t[V];
      for (int v = 0; v < V; ++v) t[v] = hn::Zero(d);
      for (int a = 0; a < count; ++a, ++blk) {
        const Vec c = hn::Set(d, *blk);
        const double* r = ti + (radial_offset(l + 2 * a) + l / 2) * kStride;
        for (int v = 0; v < V; ++v) t[v] = hn::MulAdd(hn::Load(d, r + kL * v), c, t[v]);
      }
      const double* r = tr + (radial_offset(l + 2 * b) + l / 2) * kStride;
      for (int v = 0; v < V; ++v) acc[v] = hn::MulAdd(t[v], hn::Load(d, r + kL * v), acc[v]);
    }
    for (int v = 0; v < V; ++v) fv[v] = l == 0 ? hn::Add(fv[v], acc[v]) : hn::MulAdd(acc[v], cl[v], fv[v]);
  }
  if (n == V * kL) {
    for (int v = 0; v < V; ++v) hn::StoreU(fv[v], d, f + kL * v);
  } else {
    double* tail = ws.tail.get();
    for (int v = 0; v < V; ++v) hn::Store(fv[v], d, tail + kL * v);
    std::memcpy(f, tail, sizeof(double) * static_cast<size_t>(n));
  }
}

template <int V>
void sum_chunk(int order, int n, const double* dirs, const double* w, Workspace& ws) {
  Chunk<V> ch;
  prepare<V>(dirs, n, w, ws, ch);
  eval_chunk<V, true>(order, ch, ws, AccumulateSink<V>{ws.acc.get()});
}

// Chunks of kChunk directions, then one chunk of the smallest V (1, 2, 4, ... vectors) that holds the rest.
template <int V = 1, class Fn>
HWY_INLINE void rest_chunk(std::ptrdiff_t r0, int rest, Fn&& fn) {
  if constexpr (V >= kMaxV) {
    fn(r0, rest, std::integral_constant<int, kMaxV>{});
  } else {
    if (rest <= V * kL) return fn(r0, rest, std::integral_constant<int, V>{});
    rest_chunk<2 * V>(r0, rest, fn);
  }
}

template <class Fn>
HWY_INLINE void for_chunks(std::ptrdiff_t n, Fn&& fn) {
  std::ptrdiff_t r0 = 0;
  for (; r0 + kChunk <= n; r0 += kChunk) fn(r0, kChunk, std::integral_constant<int, kMaxV>{});
  if (r0 < n) rest_chunk(r0, static_cast<int>(n - r0), fn);
}

void BasisBlock(int order, std::ptrdiff_t n, const double* dirs, double* out, std::ptrdiff_t ld) {
  Workspace& ws = workspace(order);
  for_chunks(n, [&](std::ptrdiff_t r0, int count, auto vectors) {
    block_chunk<decltype(vectors)::value>(order, count, dirs + 3 * r0, out + r0, ld, ws);
  });
}

void IsotropicForm(int order, const double* blocks, std::ptrdiff_t n, const double* wi, const double* wr, double* f) {
  Workspace& ws = workspace(order);
  for_chunks(n, [&](std::ptrdiff_t r0, int count, auto vectors) {
    isotropic_chunk<decltype(vectors)::value>(order, blocks, count, wi + 3 * r0, wr + 3 * r0, ws, f + r0);
  });
}

void BasisWeightedSum(int order, std::ptrdiff_t n, const double* dirs, const double* w, double* out) {
  Workspace& ws = workspace(order);
  const int m = (order + 1) * (order + 2) / 2;
  std::fill(ws.acc.get(), ws.acc.get() + static_cast<size_t>(m) * kL, 0.0);
  for_chunks(n, [&](std::ptrdiff_t r0, int count, auto vectors) {
    sum_chunk<decltype(vectors)::value>(order, count, dirs + 3 * r0, w + r0, ws);
  });
  const auto& norm = basis_block_detail::norms();
  for (int nn = 0, j = 0; nn <= order; ++nn)
    for (int e = 0; e <= nn; ++e, ++j) {
      double* a = ws.acc.get() + static_cast<size_t>(j) * kL;
      for (int step = 1; step < kL; step *= 2)  // the lanes, pairwise
        for (int i = 0; i + step < kL; i += 2 * step) a[i] += a[i + step];
      out[j] = norm[static_cast<size_t>(nn)] * a[0];
    }
}

}  // namespace HWY_NAMESPACE
}  // namespace icobrdf
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace icobrdf {

HWY_EXPORT(BasisBlock);
HWY_EXPORT(BasisWeightedSum);
HWY_EXPORT(IsotropicForm);

void hemisphere_basis_block(int order, Eigen::Index n, const double* dirs, double* out, Eigen::Index ld) {
  HWY_DYNAMIC_DISPATCH(BasisBlock)(order, n, dirs, out, ld);
}

void hemisphere_basis_weighted_sum(int order, Eigen::Index n, const double* dirs, const double* w, double* out) {
  HWY_DYNAMIC_DISPATCH(BasisWeightedSum)(order, n, dirs, w, out);
}

void isotropic_form_block(int order, const double* blocks, Eigen::Index n, const double* wi, const double* wr, double* f) {
  HWY_DYNAMIC_DISPATCH(IsotropicForm)(order, blocks, n, wi, wr, f);
}

}  // namespace icobrdf
#endif
