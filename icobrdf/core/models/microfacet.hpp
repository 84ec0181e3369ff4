#pragma once
// Torrance-Sparrow / Cook-Torrance microfacet reflection with GGX (Trowbridge-Reitz) or Beckmann normal
// distributions, Smith masking-shadowing and Fresnel (Schlick, exact dielectric, or none):
//   f(w_i, w_r) = D(h) F(w_i . h) G2(w_i, w_r) / (4 cos theta_i cos theta_r),   h = (w_i + w_r)/|w_i + w_r|.
// Smith masking with Lambda the distribution's Smith function, written with L(w) = cos(theta) Lambda(w),
// which stays finite at grazing:
//   height-correlated (default): G2 = 1/(1 + Lambda_i + Lambda_r)  ->  f = D F / (4 (z_i z_r + z_r L_i + z_i L_r))
//   separable:                   G2 = G1_i G1_r                    ->  f = D F / (4 (z_i + L_i)(z_r + L_r))
// The height-correlated form diverges as 1/(z_i + z_r) at double grazing; there both z are floored at
// kGrazingCosFloor inside the masking term (icobrdf/core/models/brdf_model.hpp). The separable form is bounded. Reciprocal for every parameter set;
// isotropic unless alpha_x != alpha_y. Energy: albedo <= 1 (single scattering loses energy with roughness).
// Tangent frame: the x axis of the anisotropic distribution is at azimuth `azimuth_deg` from +x.
#include <Eigen/Core>

#include <string>

#include "icobrdf/core/models/brdf_model.hpp"
#include "icobrdf/core/models/microfacet_params.hpp"

namespace icobrdf {

// Normal distribution D(h) [1/sr] for h a unit vector in the tangent frame, normalized so that the
// integral of D(h) h_z dOmega_h over the hemisphere is 1. Below the horizon (h_z < 0) D = 0; at h_z = 0
// GGX takes its finite formula value and Beckmann its limit 0.
//   GGX:      D = 1 / (pi ax ay (hx^2/ax^2 + hy^2/ay^2 + hz^2)^2)
//   Beckmann: D = exp(-(hx^2/ax^2 + hy^2/ay^2)/hz^2) / (pi ax ay hz^4)
double microfacet_d(MicrofacetDistribution dist, const Eigen::Vector3d& h, double ax, double ay);

// L(w) = w_z Lambda(w) for w in the tangent frame, w_z >= 0, q = sqrt(ax^2 wx^2 + ay^2 wy^2):
//   GGX:      L = (sqrt(wz^2 + q^2) - wz)/2 = q^2 / (2 (sqrt(wz^2 + q^2) + wz))
//   Beckmann: L = (q exp(-a^2)/sqrt(pi) - wz erfc(a))/2, a = wz / q
// Smith G1(w) = w_z / (w_z + L(w)); L = 0 at the normal, L = q/2 (GGX) or q/(2 sqrt(pi)) (Beckmann) at z = 0.
double smith_z_lambda(MicrofacetDistribution dist, const Eigen::Vector3d& w, double ax, double ay);


class MicrofacetModel final : public ScalarBrdfModel {
 public:
  // ArgumentError for an anisotropic Beckmann (no SOURCE name) or non-positive alphas.
  explicit MicrofacetModel(const MicrofacetParams& p);
  double value(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const override;
  // Batch form: the vectorized kernel of icobrdf/core/models/microfacet_kernel.hpp, run-time dispatched to the
  // CPU's widest vectors (the same formulas and horizon/grazing rules as value(), equal to it up to rounding:
  // a few ulps: the Beckmann exponential is Highway's vectorized exp, <= 1 ulp from std::exp, and its erfc a
  // vectorized expansion of a few ulps). Exactly reciprocal: swapping wi and wr gives bitwise the same values.
  // Beckmann D is 0 where its exponent exceeds 700 (D < 1e-290 there for alpha >= 1e-3).
  using ScalarBrdfModel::eval;
  void eval(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const override;
  // The same values, bit for bit, with the incident side (its frame and Lambda_i: a square root and a
  // division per pair) computed once for all pairs.
  void eval_row(const Eigen::Vector3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const override;
  bool is_isotropic() const override { return p_.alpha_x == p_.alpha_y; }
  std::string spec() const override;
  const MicrofacetParams& params() const { return p_; }
  double fresnel(double c) const;

 private:
  // Both batch forms: wi_stride 3 reads one incident direction per pair, 0 the same one for every pair.
  void eval_pairs(const double* wi, Eigen::Index wi_stride, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const;
  MicrofacetParams p_;
  double cos_az_, sin_az_;
};

const char* fresnel_mode_name(FresnelMode m);
const char* smith_masking_name(SmithMasking m);

}  // namespace icobrdf
