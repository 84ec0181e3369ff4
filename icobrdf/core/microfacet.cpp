#include "icobrdf/core/microfacet.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "icobrdf/core/error.hpp"
#include "icobrdf/core/fresnel.hpp"

namespace icobrdf {

double microfacet_d(MicrofacetDistribution dist, const Eigen::Vector3d& h, double ax, double ay) {
  const double x = h.x() / ax, y = h.y() / ay, z = h.z();
  if (dist == MicrofacetDistribution::Ggx) {
    if (z < 0.0) return 0.0;
    const double t = x * x + y * y + z * z;
    return 1.0 / (M_PI * ax * ay * t * t);
  }
  if (z <= 0.0) return 0.0;
  const double z2 = z * z;
  return std::exp(-(x * x + y * y) / z2) / (M_PI * ax * ay * z2 * z2);
}

double smith_z_lambda(MicrofacetDistribution dist, const Eigen::Vector3d& w, double ax, double ay) {
  const double q2 = ax * ax * w.x() * w.x() + ay * ay * w.y() * w.y();
  const double z = std::max(w.z(), 0.0);
  if (q2 == 0.0) return 0.0;
  if (dist == MicrofacetDistribution::Ggx) return q2 / (2.0 * (std::sqrt(z * z + q2) + z));
  const double q = std::sqrt(q2);
  const double a = z / q;
  return 0.5 * (q * std::exp(-a * a) / std::sqrt(M_PI) - z * std::erfc(a));
}

MicrofacetModel::MicrofacetModel(const MicrofacetParams& p) : p_(p) {
  if (p_.anisotropic && p_.distribution != MicrofacetDistribution::Ggx)
    throw ArgumentError("microfacet model: anisotropic widths are supported for GGX only");
  if (!(p_.alpha_x > 0.0) || !(p_.alpha_y > 0.0))
    throw ArgumentError("microfacet model: alphas must be > 0, got " + format_parameter(p_.alpha_x) + ", " +
                        format_parameter(p_.alpha_y));
  if (!p_.anisotropic) p_.alpha_y = p_.alpha_x;
  const double az = p_.azimuth_deg * M_PI / 180.0;
  cos_az_ = std::cos(az);
  sin_az_ = std::sin(az);
}

double MicrofacetModel::fresnel(double c) const {
  switch (p_.fresnel) {
    case FresnelMode::Schlick: return fresnel_schlick(c, p_.f0);
    case FresnelMode::Dielectric: return fresnel_dielectric(c, p_.ior);
    case FresnelMode::None: break;
  }
  return 1.0;
}

double MicrofacetModel::value(const Eigen::Vector3d& wi_world, const Eigen::Vector3d& wr_world) const {
  // Into the tangent frame (rotation about z by -azimuth).
  const auto local = [&](const Eigen::Vector3d& w) {
    return Eigen::Vector3d(cos_az_ * w.x() + sin_az_ * w.y(), -sin_az_ * w.x() + cos_az_ * w.y(), w.z());
  };
  const Eigen::Vector3d wi = local(wi_world), wr = local(wr_world);
  Eigen::Vector3d h = wi + wr;
  const double n = h.norm();
  if (n == 0.0) return 0.0;  // opposite horizontal directions: no half vector (a set of measure zero)
  h /= n;
  const double d = microfacet_d(p_.distribution, h, p_.alpha_x, p_.alpha_y);
  if (d == 0.0) return 0.0;
  // w_i . h = (1 + w_i . w_r)/|w_i + w_r| = |w_i + w_r|/2 for unit vectors: symmetric and accurate.
  const double c = std::min(0.5 * n, 1.0);
  const double f = fresnel(c);
  const double li = smith_z_lambda(p_.distribution, wi, p_.alpha_x, p_.alpha_y);
  const double lr = smith_z_lambda(p_.distribution, wr, p_.alpha_x, p_.alpha_y);
  double denom;
  if (p_.masking == SmithMasking::HeightCorrelated) {  // diverges at double grazing: floor the cosines
    const double zi = std::max(wi.z(), kGrazingCosFloor), zr = std::max(wr.z(), kGrazingCosFloor);
    denom = 4.0 * (zi * zr + (zr * li + zi * lr));
  } else {  // bounded: L > 0 off the normal
    denom = 4.0 * (wi.z() + li) * (wr.z() + lr);
  }
  if (denom == 0.0) return 0.0;  // unreachable for unit vectors (z = 0 implies L > 0); guards 0/0
  return d * f / denom;
}

namespace {

// Pairs per block of the vectorized GGX evaluation (structure-of-arrays buffers on the stack). Measured
// (Zen 4, AVX-512, streaming GGX at level 5, order 8, 2026-11-27): 32 pairs took 52-54 ms, 24 pairs 54-56,
// 64 pairs 61-63, 128 pairs 62-64, 8 pairs 75-78.
constexpr Eigen::Index kGgxBlock = 32;
using GgxArray = Eigen::Array<double, kGgxBlock, 1>;
using StridedColumn = Eigen::Map<const GgxArray, 0, Eigen::InnerStride<3>>;  // x, y or z of kGgxBlock directions (rows of 3)
// Copies n <= kGgxBlock directions (3 doubles each, `stride` doubles apart; stride 0 repeats one) into `pad`
// as a whole block, the lanes beyond n set to the harmless (0, 0, 1); returns pad's data.
const double* padded_block(const double* w, Eigen::Index stride, Eigen::Index n, std::array<double, 3 * kGgxBlock>& pad) {
  for (Eigen::Index k = 0; k < kGgxBlock; ++k)
    for (int e = 0; e < 3; ++e) pad[static_cast<size_t>(3 * k + e)] = k < n ? w[stride * k + e] : (e == 2 ? 1.0 : 0.0);
  return pad.data();
}
// Beckmann: D is set to 0 where its exponent exceeds this (there D < exp(-700) (1 + 700 alpha^2)^2 / (pi alpha^2),
// below 1e-290 for every alpha >= 1e-3; the factor n^4/h_z^4 is bounded by the same condition, so no
// overflow meets the underflow of exp).
constexpr double kBeckmannExponentMax = 700.0;

// Beckmann L = (q exp(-a^2)/sqrt(pi) - z erfc(a))/2, a = z/q, for the lanes of a block (smith_z_lambda with
// the exponential vectorized; erfc stays std::erfc, once per run of equal consecutive directions, which is
// every lane of a LUT row's replicated incident direction). `prev` carries the last direction and its L
// across blocks (prev[3] = L).
void beckmann_z_lambda_block(const GgxArray& x, const GgxArray& y, const GgxArray& z, double ax2, double ay2,
                             std::array<double, 4>& prev, GgxArray& out) {
  const GgxArray q2 = ax2 * x * x + ay2 * y * y;
  const GgxArray q = q2.sqrt();
  const GgxArray a = z / q.max(std::numeric_limits<double>::min());
  const GgxArray e = (-(a * a)).exp();
  for (Eigen::Index k = 0; k < kGgxBlock; ++k) {
    if (x[k] == prev[0] && y[k] == prev[1] && z[k] == prev[2]) {
      out[k] = prev[3];
      continue;
    }
    out[k] = q2[k] == 0.0 ? 0.0 : 0.5 * (q[k] * e[k] / std::sqrt(M_PI) - z[k] * std::erfc(a[k]));
    prev = {x[k], y[k], z[k], out[k]};
  }
}

}  // namespace

void MicrofacetModel::eval(const RowMatrix3d& wi_all, const RowMatrix3d& wr_all, Eigen::Ref<Eigen::MatrixXd> out) const {
  check_pair_shapes(wi_all, wr_all, out, 1);
  eval_pairs(wi_all.data(), 3, wr_all, out);
}

void MicrofacetModel::eval_row(const Eigen::Vector3d& wi, const RowMatrix3d& wr_all, Eigen::Ref<Eigen::MatrixXd> out) const {
  check_pair_shapes(wr_all, wr_all, out, 1);
  eval_pairs(wi.data(), 0, wr_all, out);
}

void MicrofacetModel::eval_pairs(const double* wi_data, Eigen::Index wi_stride, const RowMatrix3d& wr_all, Eigen::Ref<Eigen::MatrixXd> out) const {
  const bool ggx = p_.distribution == MicrofacetDistribution::Ggx;
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  std::array<double, 4> prev_i{nan, nan, nan, 0.0}, prev_r{nan, nan, nan, 0.0};
  const double ax = p_.alpha_x, ay = p_.alpha_y, ax2 = ax * ax, ay2 = ay * ay;
  const double inv_ax2 = 1.0 / ax2, inv_ay2 = 1.0 / ay2, d_scale = 1.0 / (M_PI * ax * ay);
  const Eigen::Index rows = wr_all.rows();
  // The incident side (its frame, unclamped z and Lambda_i) lives across blocks: with one incident direction
  // (wi_stride 0) the first block's is every block's (a short first block is the only block), computed by
  // the same instructions as for pairs, so both forms give the same bits.
  GgxArray xi, yi, zi_given, li, xr, yr, zr, valid;
  std::array<double, 3 * kGgxBlock> wi_pad, wr_pad;  // a short block's pairs, or the replicated incident direction
  for (Eigen::Index r0 = 0; r0 < rows; r0 += kGgxBlock) {
    const Eigen::Index nb = std::min(kGgxBlock, rows - r0);
    const bool new_incident = wi_stride != 0 || r0 == 0;
    // Into the tangent frame (rotation about z by -azimuth), by strided vector loads of the x, y and z
    // columns: in place for a whole block; a short block is first copied with padding pairs (0, 0, 1), and
    // one incident direction is replicated, so that every pair takes the same instructions wherever it is.
    const double* a = wi_data + wi_stride * r0;
    const double* b = wr_all.data() + 3 * r0;
    if (nb < kGgxBlock) b = padded_block(b, 3, nb, wr_pad);
    if (new_incident) {
      if (wi_stride == 0 || nb < kGgxBlock) a = padded_block(a, wi_stride, nb, wi_pad);
      const StridedColumn ax0(a), ay0(a + 1), az0(a + 2);
      xi = cos_az_ * ax0 + sin_az_ * ay0;
      yi = -sin_az_ * ax0 + cos_az_ * ay0;
      zi_given = az0;
    }
    const StridedColumn bx(b), by(b + 1), bz(b + 2);
    xr = cos_az_ * bx + sin_az_ * by;
    yr = -sin_az_ * bx + cos_az_ * by;
    zr = bz;
    // Below the horizon: f = 0; within the slack: z = 0 (icobrdf/core/brdf_model.hpp).
    valid = ((zi_given >= -kHorizonSlack) && (zr >= -kHorizonSlack)).cast<double>();
    const GgxArray zi = zi_given.max(0.0);
    zr = zr.max(0.0);
    const GgxArray hx = xi + xr, hy = yi + yr, hz = zi + zr;
    const GgxArray n2 = hx * hx + hy * hy + hz * hz;
    const GgxArray n = n2.sqrt();
    const GgxArray c = (0.5 * n).min(1.0);
    GgxArray f;
    if (p_.fresnel == FresnelMode::Schlick) {
      const GgxArray m = 1.0 - c, m2 = m * m;
      f = p_.f0 + (1.0 - p_.f0) * m2 * m2 * m;
    } else if (p_.fresnel == FresnelMode::Dielectric) {
      for (Eigen::Index k = 0; k < kGgxBlock; ++k) f[k] = fresnel_dielectric(c[k], p_.ior);
    } else {
      f.setOnes();
    }
    GgxArray lr;
    if (ggx) {
      // L = q^2 / (2 (sqrt(z^2 + q^2) + z)), 0 at the normal (q = 0).
      // (The floor only matters for q = z = 0, not a unit vector, where it makes L = 0 instead of 0/0.)
      constexpr double tiny = std::numeric_limits<double>::min();
      if (new_incident) {
        const GgxArray qi = ax2 * xi * xi + ay2 * yi * yi;
        li = qi / (2.0 * ((zi * zi + qi).sqrt() + zi)).max(tiny);
      }
      const GgxArray qr = ax2 * xr * xr + ay2 * yr * yr;
      lr = qr / (2.0 * ((zr * zr + qr).sqrt() + zr)).max(tiny);
    } else {
      if (new_incident) beckmann_z_lambda_block(xi, yi, zi, ax2, ay2, prev_i, li);
      beckmann_z_lambda_block(xr, yr, zr, ax2, ay2, prev_r, lr);
    }
    GgxArray denom;
    if (p_.masking == SmithMasking::HeightCorrelated) {
      const GgxArray zfi = zi.max(kGrazingCosFloor), zfr = zr.max(kGrazingCosFloor);
      // zr L_i + zi L_r summed as max + min of the two products: no product can be fused into the addition
      // (which would round the two orders differently), so swapping w_i and w_r gives bitwise the same sum.
      const GgxArray u = zfr * li, v = zfi * lr;
      denom = 4.0 * (zfi * zfr + (u.max(v) + u.min(v)));
    } else {
      denom = 4.0 * (zi + li) * (zr + lr);
    }
    GgxArray value;
    if (ggx) {
      // D(h/|h|) = 1 / (pi ax ay t^2), t = s / n^2, s = hx^2/ax^2 + hy^2/ay^2 + hz^2 (hz >= 0 here): the
      // division is folded into the final one, D = n^4 / (pi ax ay s^2).
      const GgxArray s = hx * hx * inv_ax2 + hy * hy * inv_ay2 + hz * hz;
      value = (d_scale * n2 * n2 * f) / (s * s * denom);
    } else {
      // D(h/|h|) = exp(-t) n^4 / (pi ax ay hz^4), t = (hx^2/ax^2 + hy^2/ay^2) / hz^2 (scale-free); its limit 0
      // at hz = 0 and beyond kBeckmannExponentMax.
      const GgxArray hz2 = hz * hz;
      const GgxArray t = (hx * hx * inv_ax2 + hy * hy * inv_ay2) / hz2.max(std::numeric_limits<double>::min());
      const GgxArray r = n2 / hz2.max(std::numeric_limits<double>::min());
      const GgxArray d = (t <= kBeckmannExponentMax).select(d_scale * (-t.min(kBeckmannExponentMax)).exp() * (r * r), 0.0);
      value = (d * f) / denom;
    }
    // Zero below the horizon, without a half vector (opposite horizontal directions) and for a vanishing
    // denominator (guards 0/0), as value() does.
    const GgxArray kept = (valid == 0.0 || n2 == 0.0 || denom == 0.0).select(0.0, value);
    out.col(0).segment(r0, nb) = kept.head(nb).matrix();
  }
}

const char* fresnel_mode_name(FresnelMode m) {
  switch (m) {
    case FresnelMode::Schlick: return "schlick";
    case FresnelMode::Dielectric: return "dielectric";
    case FresnelMode::None: break;
  }
  return "none";
}

const char* smith_masking_name(SmithMasking m) {
  return m == SmithMasking::HeightCorrelated ? "correlated" : "separable";
}

std::string MicrofacetModel::spec() const {
  std::vector<std::pair<std::string, std::string>> kv;
  std::string name;
  if (p_.anisotropic) {
    name = "ggx-aniso";
    kv = {{"alpha_x", format_parameter(p_.alpha_x)},
          {"alpha_y", format_parameter(p_.alpha_y)},
          {"azimuth", format_parameter(p_.azimuth_deg)}};
  } else {
    name = p_.distribution == MicrofacetDistribution::Ggx ? "ggx" : "beckmann";
    kv = {{"alpha", format_parameter(p_.alpha_x)}};
  }
  kv.push_back({"fresnel", fresnel_mode_name(p_.fresnel)});
  kv.push_back({"f0", format_parameter(p_.f0)});
  kv.push_back({"ior", format_parameter(p_.ior)});
  kv.push_back({"masking", smith_masking_name(p_.masking)});
  return format_model_spec(name, kv);
}

}  // namespace icobrdf
