// Compiled once per SIMD target (Highway foreach_target); see icobrdf/core/models/microfacet_kernel.hpp.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "icobrdf/core/models/microfacet_kernel.cpp"
#include <hwy/foreach_target.h>  // re-includes this file once per target
#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>

#include "icobrdf/core/models/brdf_model.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/models/microfacet_kernel.hpp"

#ifndef ICOBRDF_MICROFACET_KERNEL_ONCE
#define ICOBRDF_MICROFACET_KERNEL_ONCE
namespace icobrdf {
namespace {
// Beckmann: D is set to 0 where its exponent exceeds this (there D < exp(-700) (1 + 700 alpha^2)^2 / (pi alpha^2),
// below 1e-290 for every alpha >= 1e-3; the factor n^4/h_z^4 is bounded by the same condition, so no
// overflow meets the underflow of exp).
constexpr double kBeckmannExponentMax = 700.0;
// Lanes of the widest vector of any target Highway has (256 bytes: SVE, RVV; AVX-512 has 8 doubles): the size
// of the per-lane buffers (each target checks its own width against it below; HWY_MAX_BYTES is the width of
// the target being compiled, so it cannot size a buffer shared by all).
constexpr std::ptrdiff_t kMaxLanes = 32;
constexpr double kTiny = std::numeric_limits<double>::min();

// Copies n <= lanes directions (3 doubles each, `stride` doubles apart; stride 0 repeats one) into `pad` as a
// whole vector's worth, the lanes beyond n set to the harmless (0, 0, 1); returns pad.
const double* padded_directions(const double* w, std::ptrdiff_t stride, std::ptrdiff_t n, std::ptrdiff_t lanes, double* pad) {
  for (std::ptrdiff_t k = 0; k < lanes; ++k)
    for (int e = 0; e < 3; ++e) pad[3 * k + e] = k < n ? w[stride * k + e] : (e == 2 ? 1.0 : 0.0);
  return pad;
}

// erfcx(a) = exp(a^2) erfc(a) for a >= 0 as 2 P(Z) / (L + a)^2 + 1 / (sqrt(pi) (L + a)), Z = (a - L)/(a + L),
// L = kErfcxL, P(Z) = sum_j c_j T_j(Z) (Weideman's rational expansion, SIAM J. Numer. Anal. 31 (1994) 1497, on
// the real axis). The coefficients interpolate P at 29 Chebyshev nodes from 40-digit erfcx; derived by
// scripts/derive/erfcx_chebyshev.py, which measures 1.96 ulps at worst over [0, 1e9] in double precision.
constexpr double kErfcxL = 3.0;
constexpr double kErfcxChebyshev[] = {
    1.88129396519870329e+00, -1.33290391220128734e+00, 3.60465339648202876e-01,
    -7.08140105572250961e-02, 8.42887983185968727e-03, -1.98694159553685909e-05,
    -1.91275681992626788e-04, 2.30620548290717269e-05, 3.13926506442597463e-06,
    -9.26814251083452956e-07, -4.92294802463686295e-08, 3.34767487304343109e-08,
    1.01162676687855624e-09, -1.27045221420483803e-09, -4.73273491280280693e-11,
    5.12580813242917936e-11, 3.60147583621073939e-12, -2.10946661386413469e-12,
    -2.76539693333423661e-13, 8.15868788109163862e-14, 1.93689530126616084e-14,
    -2.45231861632569084e-15, -1.21300670850087177e-15, 6.40693933451340887e-18,
    6.55774271330331653e-17, 7.29481124108174275e-18, -2.75515594435196110e-18,
    -7.75855550724826357e-19, 4.70816788701372084e-20,
};
constexpr int kErfcxTerms = static_cast<int>(sizeof(kErfcxChebyshev) / sizeof(kErfcxChebyshev[0]));
}  // namespace
}  // namespace icobrdf
#endif

HWY_BEFORE_NAMESPACE();
namespace icobrdf {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;
using V = hn::Vec<D>;
static_assert(HWY_MAX_BYTES / sizeof(double) <= kMaxLanes, "the per-lane buffers are narrower than this target's vectors");

// One side of a pair in the tangent frame: x, y, the given z (for the horizon test) and z clamped at 0.
struct Side {
  V x, y, z_given, z;
};

HWY_INLINE Side LoadSide(D d, const double* w, V cos_az, V sin_az) {
  V wx, wy, wz;
  hn::LoadInterleaved3(d, w, wx, wy, wz);
  Side s;
  s.x = hn::Add(hn::Mul(cos_az, wx), hn::Mul(sin_az, wy));
  s.y = hn::Sub(hn::Mul(cos_az, wy), hn::Mul(sin_az, wx));
  s.z_given = wz;
  s.z = hn::Max(wz, hn::Zero(d));
  return s;
}

// erfcx(a) = exp(a^2) erfc(a), a >= 0 (the expansion above, Clenshaw's recurrence).
HWY_INLINE V Erfcx(D d, V a) {
  const V l = hn::Set(d, kErfcxL);
  const V inv = hn::Div(hn::Set(d, 1.0), hn::Add(l, a));
  const V z = hn::Mul(hn::Sub(a, l), inv), z2 = hn::Add(z, z);
  V b1 = hn::Zero(d), b2 = hn::Zero(d);
  for (int j = kErfcxTerms - 1; j >= 1; --j) {
    // b_j = 2 z b_{j+1} - b_{j+2} + c_j with c_j - b_{j+2} formed off the chain: one multiply-add per term on it.
    const V b0 = hn::MulAdd(z2, b1, hn::Sub(hn::Set(d, kErfcxChebyshev[j]), b2));
    b2 = b1;
    b1 = b0;
  }
  const V p = hn::Add(hn::MulSub(z, b1, b2), hn::Set(d, kErfcxChebyshev[0]));
  return hn::Mul(inv, hn::MulAdd(hn::Add(p, p), inv, hn::Set(d, 1.0 / std::sqrt(M_PI))));
}

// L(w) = num / den of one side (microfacet.hpp). GGX: num = q^2, den = 2 (sqrt(z^2 + q^2) + z), floored (only
// q = z = 0, not a unit vector, meets the floor: L = 0 there instead of 0/0); the division is left to the final
// one. Beckmann: num = L = (q exp(-a^2)/sqrt(pi) - z erfc(a))/2 = exp(-a^2) (q/sqrt(pi) - z erfcx(a))/2, a = z/q,
// 0 at the normal (q = 0), and den = 1.
struct SideL {
  V num, den;
};

HWY_INLINE SideL SideLOf(D d, const Side& s, bool ggx, V ax2, V ay2) {
  const V q2 = hn::Add(hn::Mul(ax2, hn::Mul(s.x, s.x)), hn::Mul(ay2, hn::Mul(s.y, s.y)));
  if (ggx) {
    const V root = hn::Sqrt(hn::Add(hn::Mul(s.z, s.z), q2));
    return {q2, hn::Max(hn::Mul(hn::Set(d, 2.0), hn::Add(root, s.z)), hn::Set(d, kTiny))};
  }
  const V q = hn::Sqrt(q2);
  const V a = hn::Div(s.z, hn::Max(q, hn::Set(d, kTiny)));
  const V e = hn::Exp(d, hn::Neg(hn::Mul(a, a)));
  const V l = hn::Mul(hn::Mul(hn::Set(d, 0.5), e), hn::Sub(hn::Mul(q, hn::Set(d, 1.0 / std::sqrt(M_PI))), hn::Mul(s.z, Erfcx(d, a))));
  return {hn::IfThenZeroElse(hn::Eq(q2, hn::Zero(d)), l), hn::Set(d, 1.0)};
}

// Fresnel at c = w_i . h: Schlick f0 + (1 - f0)(1 - c)^5, or the exact dielectric (icobrdf/core/models/fresnel.hpp:
// total reflection where g^2 < 0, 0 where g + c = 0), or 1.
HWY_INLINE V FresnelOf(D d, const MicrofacetParams& p, V c) {
  const V one = hn::Set(d, 1.0);
  if (p.fresnel == FresnelMode::Schlick) {
    const V m = hn::Sub(one, c), m2 = hn::Mul(m, m);
    return hn::Add(hn::Set(d, p.f0), hn::Mul(hn::Mul(hn::Mul(hn::Set(d, 1.0 - p.f0), m2), m2), m));
  }
  if (p.fresnel == FresnelMode::Dielectric) {
    const V g2 = hn::Add(hn::Set(d, p.ior * p.ior - 1.0), hn::Mul(c, c));
    const V g = hn::Sqrt(hn::Max(g2, hn::Zero(d)));
    const V gpc = hn::Add(g, c), gmc = hn::Sub(g, c);
    const V a = hn::Div(gmc, gpc);
    const V b = hn::Div(hn::Sub(hn::Mul(c, gpc), one), hn::Add(hn::Mul(c, gmc), one));
    const V f = hn::Mul(hn::Mul(hn::Mul(hn::Set(d, 0.5), a), a), hn::Add(one, hn::Mul(b, b)));
    return hn::IfThenElse(hn::Lt(g2, hn::Zero(d)), one, hn::IfThenZeroElse(hn::Eq(gpc, hn::Zero(d)), f));
  }
  return one;
}

void ErfcValues(const double* a, std::ptrdiff_t n, double* out) {
  const D d;
  const std::ptrdiff_t lanes = static_cast<std::ptrdiff_t>(hn::Lanes(d));
  HWY_ALIGN double buf[kMaxLanes];
  for (std::ptrdiff_t i = 0; i < n; i += lanes) {
    const std::ptrdiff_t nb = std::min(lanes, n - i);
    for (std::ptrdiff_t k = 0; k < lanes; ++k) buf[k] = k < nb ? a[i + k] : 0.0;
    const V x = hn::Load(d, buf);
    hn::Store(hn::Mul(hn::Exp(d, hn::Neg(hn::Mul(x, x))), Erfcx(d, x)), d, buf);
    std::copy(buf, buf + nb, out + i);
  }
}

void MicrofacetValues(const MicrofacetParams& p, double cos_azimuth, double sin_azimuth, const double* wi, std::ptrdiff_t wi_stride,
                      const double* wr, std::ptrdiff_t n, double* out) {
  const bool ggx = p.distribution == MicrofacetDistribution::Ggx;
  const D d;
  const std::ptrdiff_t lanes = static_cast<std::ptrdiff_t>(hn::Lanes(d));
  const double ax = p.alpha_x, ay = p.alpha_y;
  const V cos_az = hn::Set(d, cos_azimuth), sin_az = hn::Set(d, sin_azimuth);
  const V ax2 = hn::Set(d, ax * ax), ay2 = hn::Set(d, ay * ay);
  const V inv_ax2 = hn::Set(d, 1.0 / (ax * ax)), inv_ay2 = hn::Set(d, 1.0 / (ay * ay));
  const V d_scale = hn::Set(d, 1.0 / (M_PI * ax * ay));
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0), four = hn::Set(d, 4.0), tiny = hn::Set(d, kTiny);
  const V horizon = hn::Set(d, -kHorizonSlack), grazing = hn::Set(d, kGrazingCosFloor);
  HWY_ALIGN double wi_pad[3 * kMaxLanes], wr_pad[3 * kMaxLanes], tail[kMaxLanes];
  Side si{zero, zero, zero, zero};
  SideL li{zero, one};
  for (std::ptrdiff_t r0 = 0; r0 < n; r0 += lanes) {
    const std::ptrdiff_t nb = std::min(lanes, n - r0);
    // The incident side lives across vectors: with one incident direction (wi_stride 0) the first vector's is
    // every vector's (a short first vector is the only one), so both forms take the same instructions.
    if (wi_stride != 0 || r0 == 0) {
      const double* a = wi + wi_stride * r0;
      if (wi_stride == 0 || nb < lanes) a = padded_directions(a, wi_stride, nb, lanes, wi_pad);
      si = LoadSide(d, a, cos_az, sin_az);
      li = SideLOf(d, si, ggx, ax2, ay2);
    }
    const double* b = wr + 3 * r0;
    if (nb < lanes) b = padded_directions(b, 3, nb, lanes, wr_pad);
    const Side sr = LoadSide(d, b, cos_az, sin_az);
    const SideL lr = SideLOf(d, sr, ggx, ax2, ay2);
    // Below the horizon: f = 0; within the slack: z = 0 (icobrdf/core/models/brdf_model.hpp).
    const auto below = hn::Or(hn::Lt(si.z_given, horizon), hn::Lt(sr.z_given, horizon));
    const V hx = hn::Add(si.x, sr.x), hy = hn::Add(si.y, sr.y), hz = hn::Add(si.z, sr.z);
    const V n2 = hn::Add(hn::Add(hn::Mul(hx, hx), hn::Mul(hy, hy)), hn::Mul(hz, hz));
    // w_i . h = |w_i + w_r| / 2 for unit vectors: symmetric and accurate (not needed without Fresnel).
    const V f = p.fresnel == FresnelMode::None ? one : FresnelOf(d, p, hn::Min(hn::Mul(hn::Set(d, 0.5), hn::Sqrt(n2)), one));
    // The masking denominator times den_i den_r (L = num / den on each side), so that GGX's L costs no
    // division of its own: height-correlated 4 (z_i z_r + z_r L_i + z_i L_r) den_i den_r
    // = 4 (A_i A_r + A_r num_i + A_i num_r), A = z den; separable 4 (z_i + L_i)(z_r + L_r) den_i den_r
    // = 4 (z_i den_i + num_i)(z_r den_r + num_r). Beckmann's den = 1 leaves its terms as they were.
    V denom;
    if (p.masking == SmithMasking::HeightCorrelated) {
      const V ai = hn::Mul(hn::Max(si.z, grazing), li.den), ar = hn::Mul(hn::Max(sr.z, grazing), lr.den);
      // A_r num_i + A_i num_r summed as max + min of the two products: no product can be fused into the addition
      // (which would round the two orders differently), so swapping w_i and w_r gives bitwise the same sum.
      const V u = hn::Mul(ar, li.num), v = hn::Mul(ai, lr.num);
      denom = hn::Mul(four, hn::Add(hn::Mul(ai, ar), hn::Add(hn::Max(u, v), hn::Min(u, v))));
    } else {
      denom = hn::Mul(hn::Mul(four, hn::Add(hn::Mul(si.z, li.den), li.num)), hn::Add(hn::Mul(sr.z, lr.den), lr.num));
    }
    V value;
    if (ggx) {
      // D(h/|h|) = 1 / (pi ax ay t^2), t = s / n^2, s = hx^2/ax^2 + hy^2/ay^2 + hz^2 (hz >= 0 here): the division
      // folded into the final one, D = n^4 / (pi ax ay s^2).
      const V s = hn::Add(hn::Add(hn::Mul(hn::Mul(hx, hx), inv_ax2), hn::Mul(hn::Mul(hy, hy), inv_ay2)), hn::Mul(hz, hz));
      value = hn::Div(hn::Mul(hn::Mul(hn::Mul(hn::Mul(d_scale, n2), n2), f), hn::Mul(li.den, lr.den)), hn::Mul(hn::Mul(s, s), denom));
    } else {
      // D(h/|h|) = exp(-t) n^4 / (pi ax ay hz^4), t = (hx^2/ax^2 + hy^2/ay^2) / hz^2; its limit 0 at hz = 0 and
      // beyond kBeckmannExponentMax.
      const V inv_hz2 = hn::Div(one, hn::Max(hn::Mul(hz, hz), tiny));
      const V t = hn::Mul(hn::Add(hn::Mul(hn::Mul(hx, hx), inv_ax2), hn::Mul(hn::Mul(hy, hy), inv_ay2)), inv_hz2);
      const V r = hn::Mul(n2, inv_hz2);
      const V e = hn::Exp(d, hn::Neg(hn::Min(t, hn::Set(d, kBeckmannExponentMax))));
      const V dv = hn::IfThenElseZero(hn::Le(t, hn::Set(d, kBeckmannExponentMax)), hn::Mul(hn::Mul(d_scale, e), hn::Mul(r, r)));
      value = hn::Div(hn::Mul(dv, f), denom);
    }
    // Zero below the horizon, without a half vector (opposite horizontal directions) and for a vanishing
    // denominator (guards 0/0), as value() does.
    const auto dropped = hn::Or(below, hn::Or(hn::Eq(n2, zero), hn::Eq(denom, zero)));
    const V kept = hn::IfThenZeroElse(dropped, value);
    if (nb == lanes) {
      hn::StoreU(kept, d, out + r0);
    } else {
      hn::Store(kept, d, tail);
      std::copy(tail, tail + nb, out + r0);
    }
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace icobrdf
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace icobrdf {

HWY_EXPORT(MicrofacetValues);
HWY_EXPORT(ErfcValues);

void microfacet_kernel_erfc(const double* a, std::ptrdiff_t n, double* out) {
  for (std::ptrdiff_t i = 0; i < n; ++i)
    if (!(a[i] >= 0.0)) throw ArgumentError("microfacet kernel erfc: argument " + std::to_string(i) + " is " + std::to_string(a[i]) + ", expected >= 0");
  if (n > 0) HWY_DYNAMIC_DISPATCH(ErfcValues)(a, n, out);
}

void microfacet_kernel_values(const MicrofacetParams& p, double cos_azimuth, double sin_azimuth, const double* wi,
                              std::ptrdiff_t wi_stride, const double* wr, std::ptrdiff_t n, double* out) {
  // Whole vectors of incident rows are loaded de-interleaved, which needs rows of 3 one after another.
  if (wi_stride != 0 && wi_stride != 3)
    throw ArgumentError("microfacet kernel: incident stride " + std::to_string(wi_stride) + ", expected 0 (one direction) or 3 (rows of 3)");
  if (n <= 0) return;
  HWY_DYNAMIC_DISPATCH(MicrofacetValues)(p, cos_azimuth, sin_azimuth, wi, wi_stride, wr, n, out);
}

}  // namespace icobrdf
#endif
