#pragma once
// RGL measured materials (the .bsdf files of the RGL material database, rendered by Mitsuba's `measured`
// BSDF; Dupuy & Jakob 2018, "An Adaptive Parameterization for Efficient Material Acquisition and
// Rendering"): reader and evaluation.
//
// Container: a tensor file (icobrdf/io/tensor_file.hpp). Fields read (all float32 unless noted; n_p = |phi_i|,
// n_t = |theta_i|):
//   description  uint8 [L]                    text
//   theta_i      [n_t]                        incident elevations of the slices [rad], strictly increasing
//   phi_i        [n_p]                        incident azimuths [rad], strictly increasing
//   ndf          [H_n, W_n]                   microfacet distribution D over (u_theta, u_phi) (below)
//   sigma        [H_s, W_s]                   projected microfacet area sigma(w_i) over (u_theta, u_phi)
//   vndf         [n_p, n_t, H_v, W_v]         visible-normal density per slice over (u_theta, u_phi)
//   luminance    [n_p, n_t, H, W]             luminance density over the sample square (H = W); Mitsuba
//                                             uses it only for importance sampling: it is validated here
//                                             (shape, finite, >= 0) and not used by eval
//   rgb          [n_p, n_t, 3, H, W]          f cos(theta_o) over the sample square, or
//   spectra      [n_p, n_t, n_l, H, W]        the same per wavelength, with
//   wavelengths  [n_l]                        [nm], strictly increasing (its presence makes a file spectral)
//   jacobian     uint8 [1]                    1: the values must be multiplied by D(u_m) / (4 sigma(u_i))
// Other fields (e.g. "version", "valid") are ignored. Every check below is an InputError of one line
// naming the file and the field: a missing field, a dtype or shape other than the above, shapes that
// disagree (vndf/luminance/values vs theta_i/phi_i, luminance vs values, H != W), tables smaller than
// 2 x 2, non-finite values, negative vndf/luminance values, a vndf slice that integrates to 0, sigma <= 0
// when jacobian is 1, a phi_i range that is not 2 pi, pi or pi/2 (n_p > 2).
//
// Evaluation (as Mitsuba 3's measured BSDF; f returned, not f cos): with w_i the illumination direction
// (Mitsuba's si.wi, the one that selects the slice) and w_r = Mitsuba's wo, both above the horizon
// (z > 0; otherwise f = 0, as Mitsuba):
//   1. Symmetry reduction (n_p > 2 only): r = round(2 pi / (phi_last - phi_first)). r = 2: when w_i.y >= 0,
//      both directions are rotated by pi about the normal. r = 4: x is negated in both when w_i.x >= 0, y
//      when w_i.y >= 0. (Mitsuba leaves r unset for isotropic files; no reduction is applied here then.)
//   2. m = normalize(w_i + w_r); theta = 2 asin(|w - z| / 2), phi = atan2(y, x) for w_i and m;
//      u(theta) = sqrt(2 theta / pi), u(phi) = (phi + pi) / (2 pi); for m the azimuth is phi_m - phi_i when
//      n_p <= 2 (isotropic) and phi_m otherwise, wrapped to [0, 1).
//   3. The vndf warp of slice parameters (phi_i, theta_i) (icobrdf/core/tables/marginal_warp.hpp, inverse direction, x =
//      u_theta along W_v, y = u_phi along H_v) maps u_m to a sample s in the unit square.
//   4. v_c = the value table at s (bilinear, x along W) with parameters (phi_i, theta_i, lambda_c)
//      (icobrdf/core/tables/bilinear_slices.hpp; lambda_c = 0, 1, 2 for rgb, the wavelength for spectra).
//   5. jacobian: v_c *= ndf(u_m) / (4 sigma(u(theta_i), u(phi_i))) (bilinear, no parameters).
//   6. f_c = v_c / max(cos theta_r, kGrazingCosFloor).
// Parameters between nodes are interpolated linearly in radians (nanometres) and held at the ends.
// Measured data are not reciprocal: f(w_i, w_r) != f(w_r, w_i) in general.
#include <memory>
#include <string>
#include <vector>

#include "icobrdf/core/tables/bilinear_slices.hpp"
#include "icobrdf/core/models/brdf_model.hpp"
#include "icobrdf/core/tables/marginal_warp.hpp"

namespace icobrdf {

struct RglBsdf {
  std::string path, description;
  bool spectral = false;
  bool jacobian = false;
  int reduction = 1;                 // 1 (none), 2 or 4
  std::vector<double> theta_i, phi_i;
  std::vector<double> wavelengths;   // nm (spectral); empty for rgb
  MarginalWarp2D vndf;
  BilinearSlices ndf, sigma, values;
  int sample_width = 0, sample_height = 0;  // W, H of the value tables
  // Per slice of `values` (slice order of its ParameterGrid): the standard deviation of independent noise on that
  // H x W table, estimated from its second differences along u and v (icobrdf/core/tables/grid_noise.hpp); NaN
  // when the table is too small for an estimate.
  std::vector<double> noise_sigma;
  bool isotropic() const { return phi_i.size() <= 2; }
};

RglBsdf read_rgl_bsdf(const std::string& path);

// f [1/sr] of an RGL material at the channel parameters `lambdas` (for rgb files 0, 1, 2 select R, G, B; for
// spectral files wavelengths in nm, interpolated between the file's).
class RglModel final : public BrdfModel {
 public:
  RglModel(std::shared_ptr<const RglBsdf> bsdf, std::vector<double> lambdas, std::string spec);
  using BrdfModel::eval;
  int channels() const override { return static_cast<int>(lambdas_.size()); }
  void eval(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const override;
  bool is_isotropic() const override { return false; }  // not exactly: the tables need not be mirror-symmetric
  bool is_reciprocal() const override { return false; }
  std::string spec() const override { return spec_; }  // a SOURCE text, not a parse_model spec
  const RglBsdf& bsdf() const { return *bsdf_; }
  // The standard deviation [1/sr] of the noise on the values eval() looks up at the pairs (rows x channels): the
  // noise of the tables' nodes (RglBsdf::noise_sigma; the variance of the slices blended with the blend's
  // weights, not reduced by the interpolation), times the factor eval applies to the table's value (steps 5-6);
  // 0 below the horizon, NaN where a table has no estimate.
  void noise_sigma(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const;

 private:
  // Steps 1-3 and the factor of steps 5-6 at one pair.
  struct Lookup {
    bool above = false;  // both directions above the horizon
    double phi_i = 0.0, theta_i = 0.0;
    Eigen::Vector2d sample = Eigen::Vector2d::Zero();
    double scale = 0.0;
  };
  Lookup lookup(Eigen::Vector3d wi, Eigen::Vector3d wr) const;
  // The blend's variance of the slices' noise (RglBsdf::noise_sigma) at parameters (phi_i, theta_i, lambda), as a sigma.
  double node_noise(const double* params) const;
  // eval (noise false) or noise_sigma (noise true).
  void fill(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out, bool noise) const;
  std::shared_ptr<const RglBsdf> bsdf_;
  std::vector<double> lambdas_;
  std::string spec_;
};

}  // namespace icobrdf
