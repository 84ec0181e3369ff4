#pragma once
// RenderMaterial: a material for renderers, built once from any SOURCE (icobrdf/io/brdf_source.hpp: analytic
// models, bank and spectrum materials of every representation, measured files), then queried one sample at a
// time, in double or float, from several threads at once, without allocating memory per call (but see
// "Evaluation" for measured SOURCEs):
//   eval(w_i, w_r)        f [1/sr] per channel, the regular part (delta parts excluded, as pbrt-v4's f());
//   pdf(w_i, w_r)         the density of sample() over w_r [1/sr], regular part only;
//   sample(w_i, u1, u2)   {w_r, weight = f cos(theta_r) / pdf per channel, pdf, flags}.
// Conventions (SPEC-NOTES): unit vectors, +z the normal, w_i and w_r both pointing away from the surface;
// reflection only: a w_i or w_r below the horizon (z < 0) gives f = 0, pdf = 0 and no sample. Inputs are not
// checked for unit length per call (a renderer's hot path); non-finite inputs give no sample.
//
// Sampling: a mixture over the material's parts, chosen per draw by u2 with probabilities proportional to
// their directional albedos at w_i (tables over the incident direction built with the material):
//   - delta parts (mirror, retroreflector, icobrdf/core/models/brdf_model.hpp DeltaPart of weight w; albedo w):
//     w_r the image of w_i, pdf = the part's probability P (a discrete probability, as pbrt-v4 reports it),
//     weight = w / P, flags Reflection | Specular;
//   - GGX microfacet terms of a model (icobrdf/core/models/microfacet.hpp): visible-normal sampling
//     (icobrdf/core/models/ggx_vndf.hpp), albedo per incident node by 32 x 32 stratified draws;
//   - everything else of the regular part (a stored lobe and modes, other models, measured data): the
//     half-vector tables of icobrdf/core/tables/half_vector_table.hpp over the incident nodes, built from the
//     material's own values (a lobe's on its own t warp, so cells subdivide its h nodes' spacing).
// Mixing is one-sample multiple importance sampling with the balance heuristic: every draw's weight is
// f_regular cos / (sum over regular parts of P_part pdf_part), so the estimator of the directional albedo is
// unbiased wherever some part's density is positive (the table's floor makes it positive wherever w_r can
// be). pdf() returns that same mixture density. A draw whose w_r falls below the horizon (visible normals and
// tables can give one) has flags None and weight 0: it counts as a zero in an estimator.
// Flags (pbrt-v4's BxDFFlags, Mitsuba 3's lobe types): Reflection always; Specular for delta draws; Glossy
// for GGX draws and table draws of lobes and measured data; Diffuse for table draws of other models and of
// modes alone. flags() is the union over the material's parts.
//
// Evaluation per sample: models as sums of their terms (each term's pair formula); stored materials as their
// lobe (icobrdf/core/models/half_angle_factors.hpp HalfAnglePairEvaluator, bitwise the batch values) plus modes (the basis at both
// directions in one pass, hemisphere_basis_eval_pair, contracted with a copy of the coefficients whose columns are
// padded to a multiple of 4 rows: channels x M x 4 ceil(M / 4) doubles, 0.43 MB per channel at order 20;
// order <= kMaxPointModeOrder; f = max(0, modes + lobe) as icobrdf/io/material_eval.hpp; modes of
// order 0, a constant such as a paint's Lambertian part, are added as that constant without evaluating the basis);
// measured SOURCEs and model kinds without a pair formula go through their batch evaluation with one row
// (which allocates). Channels: at most kMaxMaterialChannels (a 1-channel model term is broadcast).
// Float forms convert to double and back: their values are the double values rounded to float.
#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "icobrdf/core/models/brdf_model.hpp"
#include "icobrdf/core/models/half_angle_factors.hpp"
#include "icobrdf/core/spectrum/spectrum.hpp"
#include "icobrdf/core/tables/half_vector_table.hpp"
#include "icobrdf/io/brdf_source.hpp"

namespace icobrdf {

inline constexpr int kMaxMaterialChannels = 16;
// Highest mode order evaluated per sample without allocation ((N + 1)(N + 2) / 2 = 231 basis values).
inline constexpr int kMaxPointModeOrder = 20;

// pbrt-v4's BxDFFlags (reflection part).
enum MaterialFlags : std::uint32_t {
  kMaterialNone = 0,
  kMaterialReflection = 1,
  kMaterialDiffuse = 4,
  kMaterialGlossy = 8,
  kMaterialSpecular = 16,
};

// Values per channel, on the stack (no heap memory).
template <class Real>
using MaterialColor = Eigen::Matrix<Real, Eigen::Dynamic, 1, 0, kMaxMaterialChannels, 1>;

template <class Real>
struct MaterialSample {
  Eigen::Matrix<Real, 3, 1> wr = Eigen::Matrix<Real, 3, 1>::Zero();
  MaterialColor<Real> weight;  // f cos(theta_r) / pdf per channel (delta: w / P)
  Real pdf = 0;                // [1/sr]; for a delta draw the probability of its part
  std::uint32_t flags = kMaterialNone;
  bool valid() const { return flags != kMaterialNone; }
  bool is_specular() const { return (flags & kMaterialSpecular) != 0; }
};

struct RenderMaterialOptions {
  // For an anisotropic material whose table options leave azimuth_nodes at 1, azimuth_nodes and theta_nodes
  // are set to the anisotropic values below (48 x 16 nodes would take 250 MB).
  HalfVectorTableOptions table;
  int anisotropic_azimuth_nodes = 16;
  int anisotropic_theta_nodes = 24;
  // GGX terms of models: drawn from their visible normals (true) or, like the rest, from the half-vector
  // tables (false), which hold every factor of f cos (Fresnel, masking, the horizon) and measured a smaller
  // spread of the weights (benchmarks/RESULTS.md).
  bool visible_normals = false;
};

class RenderMaterial {
 public:
  // Any SOURCE text (models, FILE.h5[#MATERIAL], measured files); the errors of open_source.
  static RenderMaterial open(const std::string& source, const RenderMaterialOptions& options = {});
  explicit RenderMaterial(std::shared_ptr<const BrdfModel> model, const RenderMaterialOptions& options = {});
  // A stored material: modes and an optional lobe (icobrdf/io/spectrum_file.hpp MaterialRecord).
  RenderMaterial(const Spectrum& modes, const std::optional<HalfAngleFactors>& lobe, const RenderMaterialOptions& options = {});
  // Any other source (evaluated through its batch form).
  explicit RenderMaterial(std::shared_ptr<const BrdfSource> source, const RenderMaterialOptions& options = {});
  ~RenderMaterial();
  RenderMaterial(RenderMaterial&&) noexcept;
  RenderMaterial& operator=(RenderMaterial&&) noexcept;

  int channels() const;
  std::uint32_t flags() const;
  bool isotropic() const;
  const std::string& spec() const;

  MaterialColor<double> eval(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const;
  MaterialColor<float> eval(const Eigen::Vector3f& wi, const Eigen::Vector3f& wr) const;
  double pdf(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const;
  float pdf(const Eigen::Vector3f& wi, const Eigen::Vector3f& wr) const;
  // u1, u2 in [0, 1).
  MaterialSample<double> sample(const Eigen::Vector3d& wi, double u1, double u2) const;
  MaterialSample<float> sample(const Eigen::Vector3f& wi, float u1, float u2) const;
  // The material's estimate of the directional albedo of its regular part at w_i (mean over channels of
  // max(f, 0)), the sum of the parts' albedo tables; delta parts add their weights.
  double albedo_estimate(const Eigen::Vector3d& wi) const;
  // The reflectance of the delta parts (the sum of their weights; 0 without any), the same for every w_i.
  double delta_albedo() const;

  struct Impl;

 private:
  explicit RenderMaterial(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace icobrdf
