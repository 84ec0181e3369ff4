// Block evaluation of the hemisphere basis K_n^l with the directions innermost (icobrdf/core/hemisphere_basis.hpp:
// hemisphere_basis_block, hemisphere_basis_weighted_sum).
//
// Directions are taken in chunks of 4 V (V vectors of four doubles; one AVX register each). Every step of
// the recurrences (radial rows, azimuthal powers, products) is then V full vector operations on data
// that stays in L1, instead of one short loop per direction. The arithmetic is that of
// hemisphere_basis_eval: Lambert radius rho^2 = (x^2 + y^2) / (1 + z), unit azimuth (x, y) / |(x, y)|,
// cos(l phi) + i sin(l phi) by repeated complex multiplication, the Zernike rows by the Shakibaei-Paramesran
// recurrence (icobrdf/core/zernike.hpp), K = (sqrt((n + 1) / pi) R) az. Only the radial rows n - 1, n - 2 are kept,
// so the workspace is O(order) per direction, not O(order^2).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <type_traits>
#include <vector>

#if defined(__AVX__)
#include <immintrin.h>
#endif

#include "icobrdf/core/hemisphere_basis.hpp"
#include "icobrdf/core/simd4.hpp"
#include "icobrdf/core/zernike.hpp"


namespace icobrdf {

namespace {

using simd4::v4d;
using simd4::v4l;
using simd4::splat;
using simd4::storeu;
constexpr int kLanes = 4;
constexpr int kMaxVectors = 8;  // largest chunk: 32 directions

inline v4d select(v4l mask, v4d a, v4d b) { return (v4d)((mask & (v4l)a) | (~mask & (v4l)b)); }
inline v4d vsqrt(v4d a) {
#if defined(__AVX__)
  return (v4d)_mm256_sqrt_pd((__m256d)a);
#else
  return v4d{std::sqrt(a[0]), std::sqrt(a[1]), std::sqrt(a[2]), std::sqrt(a[3])};
#endif
}

// sqrt((n + 1) / pi) for n <= 128.
const std::array<double, kMaxZernikeOrder + 1> kNorm = [] {
  std::array<double, kMaxZernikeOrder + 1> t{};
  for (int n = 0; n <= kMaxZernikeOrder; ++n) t[static_cast<size_t>(n)] = std::sqrt((n + 1) / M_PI);
  return t;
}();

// Per-thread workspace (vectors): azimuthal factors (2 order + 1) V, three radial rows (order / 2 + 1) V,
// accumulators (one per mode) for weighted sums, and a tail buffer for partial chunks.
struct Workspace {
  std::vector<v4d> az, rows, acc;
  std::vector<double> tail;
};

Workspace& workspace(int order) {
  thread_local Workspace ws;
  const size_t v = kMaxVectors, m = static_cast<size_t>((order + 1) * (order + 2) / 2);
  if (ws.az.size() < (2 * static_cast<size_t>(order) + 1) * v) ws.az.resize((2 * static_cast<size_t>(order) + 1) * v);
  if (ws.rows.size() < 3 * (static_cast<size_t>(order) / 2 + 1) * v) ws.rows.resize(3 * (static_cast<size_t>(order) / 2 + 1) * v);
  if (ws.acc.size() < m) ws.acc.resize(m);
  if (ws.tail.size() < m * kLanes * v) ws.tail.resize(m * kLanes * v);
  return ws;
}

// Lane quantities of one chunk: Lambert radius, unit azimuth (c1, s1) and weight.
template <int V>
struct Chunk {
  v4d rho[V], c1[V], s1[V], w[V];
};

// Directions dirs[3 r .. 3 r + 2] for r < n (n <= 4 V); the remaining lanes are the pole with weight 0.
template <int V>
void prepare(const double* dirs, int n, const double* w, Chunk<V>& ch) {
  alignas(32) double x[kLanes * V], y[kLanes * V], z[kLanes * V], ww[kLanes * V];
  for (int r = 0; r < kLanes * V; ++r) {
    const bool in = r < n;
    x[r] = in ? dirs[3 * r] : 0.0;
    y[r] = in ? dirs[3 * r + 1] : 0.0;
    z[r] = in ? dirs[3 * r + 2] : 1.0;
    ww[r] = !in ? 0.0 : (w ? w[r] : 1.0);
  }
  const v4d zero = splat(0.0), one = splat(1.0);
  for (int v = 0; v < V; ++v) {
    v4d xv, yv, zv;
    std::memcpy(&xv, x + kLanes * v, sizeof xv);
    std::memcpy(&yv, y + kLanes * v, sizeof yv);
    std::memcpy(&zv, z + kLanes * v, sizeof zv);
    std::memcpy(&ch.w[v], ww + kLanes * v, sizeof zv);
    const v4d zc = select(zv < zero, zero, zv);  // z down to -kHorizonSlack is the horizon
    const v4d h2 = xv * xv + yv * yv;
    const v4d r2 = h2 / (one + zc);  // rho^2 = 1 - cos(theta), without cancellation (icobrdf/core/lambert_map.hpp)
    ch.rho[v] = vsqrt(select(r2 > one, one, r2));
    const v4d s = vsqrt(h2);
    const v4l pos = s > zero;
    const v4d safe = select(pos, s, one);  // the pole: azimuth 0, every l != 0 vanishes there anyway
    ch.c1[v] = select(pos, xv / safe, one);
    ch.s1[v] = select(pos, yv / safe, zero);
  }
}

// Writes K_j of a chunk: out[j * ld + lane].
template <int V>
struct StoreSink {
  static constexpr bool kScaleRows = true;  // values times sqrt((n + 1) / pi) as they are emitted
  double* out;
  Eigen::Index ld;
  void emit(int j, const v4d* rs, const v4d* a) const {
    double* o = out + static_cast<Eigen::Index>(j) * ld;
    for (int v = 0; v < V; ++v) storeu(o + kLanes * v, rs[v] * a[v]);
  }
};

// Adds sum over lanes of R a (weights are inside a) to acc[j]; the normalization is applied at the end.
template <int V>
struct AccumulateSink {
  static constexpr bool kScaleRows = false;
  v4d* acc;
  void emit(int j, const v4d* r, const v4d* a) const {
    v4d t = r[0] * a[0];
    for (int v = 1; v < V; ++v) t += r[v] * a[v];
    acc[j] += t;
  }
};

// All K_n^l of one chunk, row n after row n of the Zernike recurrence, handed to the sink.
template <int V, bool Weighted, class Sink>
void eval_chunk(int order, const Chunk<V>& ch, Workspace& ws, const Sink& sink) {
  v4d* __restrict az = ws.az.data();
  // az[(order + l) V + v] = w az_l(phi): az_0 = 1/sqrt(2), az_l = cos(l phi), az_-l = sin(l phi).
  {
    v4d c[V], s[V];
    for (int v = 0; v < V; ++v) {
      az[order * V + v] = Weighted ? ch.w[v] * splat(M_SQRT1_2) : splat(M_SQRT1_2);
      c[v] = splat(1.0);
      s[v] = splat(0.0);
    }
    for (int l = 1; l <= order; ++l)
      for (int v = 0; v < V; ++v) {
        const v4d cn = c[v] * ch.c1[v] - s[v] * ch.s1[v];
        s[v] = s[v] * ch.c1[v] + c[v] * ch.s1[v];
        c[v] = cn;
        az[(order + l) * V + v] = Weighted ? ch.w[v] * c[v] : c[v];
        az[(order - l) * V + v] = Weighted ? ch.w[v] * s[v] : s[v];
      }
  }
  const v4d* centre = az + order * V;
  const int row_len = (order / 2 + 1) * V;
  v4d* buf[3] = {ws.rows.data(), ws.rows.data() + row_len, ws.rows.data() + 2 * row_len};
  auto emit_row = [&](int n, const v4d* r) {
    const int j0 = n * (n + 1) / 2, p = n % 2;
    const v4d nn = splat(kNorm[static_cast<size_t>(n)]);
    for (int i = 0; i <= n / 2; ++i) {
      const int m = 2 * i + p;  // |l|
      v4d rs[V];
      for (int v = 0; v < V; ++v) rs[v] = Sink::kScaleRows ? nn * r[i * V + v] : r[i * V + v];
      if (m == 0) {
        sink.emit(j0 + n / 2, rs, centre);
      } else {
        sink.emit(j0 + (n - m) / 2, rs, centre - m * V);  // l = -m
        sink.emit(j0 + (n + m) / 2, rs, centre + m * V);  // l = +m
      }
    }
  };
  for (int v = 0; v < V; ++v) buf[0][v] = splat(1.0);  // R_0^0
  emit_row(0, buf[0]);
  if (order == 0) return;
  for (int v = 0; v < V; ++v) buf[1][v] = ch.rho[v];  // R_1^1
  emit_row(1, buf[1]);
  for (int n = 2; n <= order; ++n) {
    v4d* __restrict cur = buf[n % 3];
    const v4d* __restrict prev = buf[(n - 1) % 3];
    const v4d* __restrict prev2 = buf[(n - 2) % 3];
    const int last = n / 2;
    if (n % 2 == 0) {
      // l = 2i from l' = 2i - 1, 2i + 1 of row n - 1 (indices i - 1, i); at l = 0, |l - 1| = 1.
      for (int v = 0; v < V; ++v) cur[v] = splat(2.0) * ch.rho[v] * prev[v] - prev2[v];
      for (int i = 1; i < last; ++i)
        for (int v = 0; v < V; ++v) cur[i * V + v] = ch.rho[v] * (prev[(i - 1) * V + v] + prev[i * V + v]) - prev2[i * V + v];
      for (int v = 0; v < V; ++v) cur[last * V + v] = ch.rho[v] * prev[(last - 1) * V + v];
    } else {
      // l = 2i + 1 from l' = 2i, 2i + 2 (indices i, i + 1).
      for (int i = 0; i < last; ++i)
        for (int v = 0; v < V; ++v) cur[i * V + v] = ch.rho[v] * (prev[i * V + v] + prev[(i + 1) * V + v]) - prev2[i * V + v];
      for (int v = 0; v < V; ++v) cur[last * V + v] = ch.rho[v] * prev[last * V + v];
    }
    emit_row(n, cur);
  }
}

// n <= 4 V directions into out[j * ld + r]; a partial chunk goes through the tail buffer.
template <int V>
void block_chunk(int order, int n, const double* dirs, double* out, Eigen::Index ld, Workspace& ws) {
  Chunk<V> ch;
  prepare<V>(dirs, n, nullptr, ch);
  if (n == kLanes * V) {
    eval_chunk<V, false>(order, ch, ws, StoreSink<V>{out, ld});
    return;
  }
  eval_chunk<V, false>(order, ch, ws, StoreSink<V>{ws.tail.data(), kLanes * V});
  const int m = (order + 1) * (order + 2) / 2;
  for (int j = 0; j < m; ++j)
    std::memcpy(out + static_cast<Eigen::Index>(j) * ld, ws.tail.data() + static_cast<size_t>(j) * kLanes * V,
                sizeof(double) * static_cast<size_t>(n));
}

template <int V>
void sum_chunk(int order, int n, const double* dirs, const double* w, Workspace& ws) {
  Chunk<V> ch;
  prepare<V>(dirs, n, w, ch);
  eval_chunk<V, true>(order, ch, ws, AccumulateSink<V>{ws.acc.data()});
}

// Chunks of 32 directions, then one chunk of the smallest V that holds the rest.
template <class Fn>
void for_chunks(Eigen::Index n, Fn&& fn) {
  constexpr Eigen::Index full = kLanes * kMaxVectors;
  Eigen::Index r0 = 0;
  for (; r0 + full <= n; r0 += full) fn(r0, static_cast<int>(full), std::integral_constant<int, kMaxVectors>{});
  const int rest = static_cast<int>(n - r0);
  switch ((rest + kLanes - 1) / kLanes) {
    case 0: break;
    case 1: fn(r0, rest, std::integral_constant<int, 1>{}); break;
    case 2: fn(r0, rest, std::integral_constant<int, 2>{}); break;
    case 3: fn(r0, rest, std::integral_constant<int, 3>{}); break;
    case 4: fn(r0, rest, std::integral_constant<int, 4>{}); break;
    case 5: fn(r0, rest, std::integral_constant<int, 5>{}); break;
    case 6: fn(r0, rest, std::integral_constant<int, 6>{}); break;
    case 7: fn(r0, rest, std::integral_constant<int, 7>{}); break;
    default: fn(r0, rest, std::integral_constant<int, 8>{}); break;
  }
}

}  // namespace

void hemisphere_basis_block(int order, Eigen::Index n, const double* dirs, double* out, Eigen::Index ld) {
  Workspace& ws = workspace(order);
  for_chunks(n, [&](Eigen::Index r0, int count, auto vectors) {
    block_chunk<decltype(vectors)::value>(order, count, dirs + 3 * r0, out + r0, ld, ws);
  });
}

void hemisphere_basis_weighted_sum(int order, Eigen::Index n, const double* dirs, const double* w, double* out) {
  Workspace& ws = workspace(order);
  const int m = (order + 1) * (order + 2) / 2;
  std::fill(ws.acc.begin(), ws.acc.begin() + m, splat(0.0));
  for_chunks(n, [&](Eigen::Index r0, int count, auto vectors) {
    sum_chunk<decltype(vectors)::value>(order, count, dirs + 3 * r0, w + r0, ws);
  });
  for (int nn = 0, j = 0; nn <= order; ++nn) {
    const double norm = kNorm[static_cast<size_t>(nn)];
    for (int e = 0; e <= nn; ++e, ++j) {
      const v4d a = ws.acc[static_cast<size_t>(j)];
      out[j] = norm * ((a[0] + a[1]) + (a[2] + a[3]));
    }
  }
}

}  // namespace icobrdf
