#include "icobrdf/core/models/microfacet.hpp"

#include <algorithm>
#include <cmath>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/models/fresnel.hpp"
#include "icobrdf/core/models/microfacet_kernel.hpp"

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

void MicrofacetModel::eval(const RowMatrix3d& wi_all, const RowMatrix3d& wr_all, Eigen::Ref<Eigen::MatrixXd> out) const {
  check_pair_shapes(wi_all, wr_all, out, 1);
  eval_pairs(wi_all.data(), 3, wr_all, out);
}

void MicrofacetModel::eval_row(const Eigen::Vector3d& wi, const RowMatrix3d& wr_all, Eigen::Ref<Eigen::MatrixXd> out) const {
  check_pair_shapes(wr_all, wr_all, out, 1);
  eval_pairs(wi.data(), 0, wr_all, out);
}

void MicrofacetModel::eval_pairs(const double* wi_data, Eigen::Index wi_stride, const RowMatrix3d& wr_all, Eigen::Ref<Eigen::MatrixXd> out) const {
  microfacet_kernel_values(p_, cos_az_, sin_az_, wi_data, wi_stride, wr_all.data(), wr_all.rows(), out.col(0).data());
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
