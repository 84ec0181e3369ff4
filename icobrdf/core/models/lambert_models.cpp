#include "icobrdf/core/models/lambert_models.hpp"

#include <algorithm>
#include <cmath>

namespace icobrdf {

std::string LambertModel::spec() const { return format_model_spec("lambert", {{"albedo", format_parameter(albedo_)}}); }

MinnaertModel::MinnaertModel(double k) : k_(k), c_((k + 1.0) / (2.0 * M_PI)) {}

double MinnaertModel::value(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const {
  double p = wi.z() * wr.z();
  if (k_ == 1.0) return c_;
  if (k_ < 1.0) p = std::max(wi.z(), kGrazingCosFloor) * std::max(wr.z(), kGrazingCosFloor);
  return c_ * std::pow(p, k_ - 1.0);
}

std::string MinnaertModel::spec() const { return format_model_spec("minnaert", {{"k", format_parameter(k_)}}); }

OrenNayarModel::OrenNayarModel(double sigma_deg, double albedo) : sigma_deg_(sigma_deg), albedo_(albedo) {
  const double s = sigma_deg * M_PI / 180.0, s2 = s * s;
  a_ = 1.0 - 0.5 * s2 / (s2 + 0.33);
  b_ = 0.45 * s2 / (s2 + 0.09);
}

double OrenNayarModel::value(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const {
  const double cross = wi.x() * wr.x() + wi.y() * wr.y();
  double term = 0.0;
  if (cross > 0.0) term = cross / std::max({wi.z(), wr.z(), kGrazingCosFloor});
  return albedo_ / M_PI * (a_ + b_ * term);
}

std::string OrenNayarModel::spec() const {
  return format_model_spec("oren-nayar", {{"sigma", format_parameter(sigma_deg_)}, {"albedo", format_parameter(albedo_)}});
}

}  // namespace icobrdf
