#pragma once
// The parameters of a microfacet model (icobrdf/core/models/microfacet.hpp gives the formulas): the normal
// distribution, its roughness along the tangent axes, the tangent frame's azimuth, the Fresnel term and the
// Smith masking form. A plain value shared by the model and its vectorized kernel
// (icobrdf/core/models/microfacet_kernel.hpp), so that neither includes the other.

namespace icobrdf {

enum class MicrofacetDistribution { Ggx, Beckmann };
enum class FresnelMode { Schlick, Dielectric, None };  // spec names: schlick, dielectric, none
enum class SmithMasking { HeightCorrelated, Separable };  // spec names: correlated, separable

struct MicrofacetParams {
  MicrofacetDistribution distribution = MicrofacetDistribution::Ggx;
  bool anisotropic = false;  // named "ggx-aniso": alpha_x, alpha_y, azimuth; else "ggx"/"beckmann": alpha
  double alpha_x = 0.3;      // roughness along the tangent x axis (= alpha when isotropic)
  double alpha_y = 0.3;
  double azimuth_deg = 0.0;  // azimuth of the tangent x axis [deg]
  FresnelMode fresnel = FresnelMode::Schlick;
  double f0 = 0.04;          // Schlick's normal-incidence reflectance
  double ior = 1.5;          // relative index of refraction for the dielectric Fresnel
  SmithMasking masking = SmithMasking::HeightCorrelated;
};

}  // namespace icobrdf
