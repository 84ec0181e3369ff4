#pragma once
// The vectorized microfacet kernel behind MicrofacetModel::eval and eval_row (icobrdf/core/models/microfacet.hpp):
// f at n pairs of directions, run-time dispatched to the CPU's widest vectors (Google Highway;
// icobrdf/core/support/simd_target.hpp), so a portable build evaluates GGX and Beckmann at AVX-512 or AVX2 width.
// The formulas and horizon/grazing rules are microfacet.hpp's; the values equal value()'s up to rounding (a
// few ulps; Beckmann's exponential is Highway's vectorized exp, <= 1 ulp from std::exp by its documentation,
// and its erfc is exp(-a^2) erfcx(a) with erfcx a Chebyshev expansion of about 2 ulps, vectorized too: see
// microfacet_kernel_erfc). Exactly reciprocal: swapping the incident and remitted directions gives bitwise the
// same values, on every target. Different targets differ in rounding only.
#include <cstddef>

#include "icobrdf/core/models/microfacet_params.hpp"

namespace icobrdf {

// out[k] = f(wi_k, wr_k) for k < n, f the microfacet model of `p` (alpha_y used as given: MicrofacetModel sets
// it to alpha_x for an isotropic model) with its tangent frame at the azimuth whose cosine and sine are given. wr: n directions as rows of 3 doubles (x, y, z), world frame. wi: n such
// rows (wi_stride 3), or one direction that is every pair's (wi_stride 0; its frame and Lambda then computed
// once, by the same instructions as for pairs: the same bits as repeating it). ArgumentError for another stride.
void microfacet_kernel_values(const MicrofacetParams& p, double cos_azimuth, double sin_azimuth, const double* wi,
                              std::ptrdiff_t wi_stride, const double* wr, std::ptrdiff_t n, double* out);

// out[k] = erfc(a[k]) for a[k] >= 0 as the kernel's Beckmann term computes it: exp(-a^2) erfcx(a), erfcx by
// the Chebyshev expansion of scripts/derive/erfcx_chebyshev.py (about 2 ulps), the exponential Highway's (<= 1
// ulp; a^2 rounded, so the relative error grows as a^2 ulp: 1e-13 near a = 26, where erfc underflows).
// ArgumentError for a negative or NaN argument. Exposed for its accuracy test.
void microfacet_kernel_erfc(const double* a, std::ptrdiff_t n, double* out);

}  // namespace icobrdf
