#include "icobrdf/core/models/lobe_models.hpp"

#include <algorithm>
#include <cmath>

#include "icobrdf/core/support/error.hpp"

namespace icobrdf {

namespace {
// max(0, c)^n with 0^0 = 0 so that the lobe is zero wherever its base is not positive.
double lobe(double c, double n) { return c > 0.0 ? std::pow(c, n) : 0.0; }
}  // namespace

PhongModel::PhongModel(double n, double ks) : n_(n), ks_(ks), c_(ks * (n + 2.0) / (2.0 * M_PI)) {}

double PhongModel::value(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const {
  return c_ * lobe(-wi.x() * wr.x() - wi.y() * wr.y() + wi.z() * wr.z(), n_);
}

std::string PhongModel::spec() const {
  return format_model_spec("phong", {{"n", format_parameter(n_)}, {"ks", format_parameter(ks_)}});
}

double BlinnPhongModel::normalization(double n) {
  return (n + 2.0) * (n + 4.0) / (8.0 * M_PI * (n + std::exp2(-0.5 * n)));
}

BlinnPhongModel::BlinnPhongModel(double n, double ks) : n_(n), ks_(ks), c_(ks * normalization(n)) {}

double BlinnPhongModel::value(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const {
  const Eigen::Vector3d s = wi + wr;
  const double len = s.norm();
  if (len == 0.0) return 0.0;  // opposite horizontal directions: h undefined, h_z -> 0
  return c_ * lobe(s.z() / len, n_);
}

std::string BlinnPhongModel::spec() const {
  return format_model_spec("blinn-phong", {{"n", format_parameter(n_)}, {"ks", format_parameter(ks_)}});
}

LafortuneModel::LafortuneModel(double cx, double cy, double cz, double n, double azimuth_deg)
    : cx_(cx), cy_(cy), cz_(cz), n_(n), azimuth_deg_(azimuth_deg) {
  // |w_i^T M w_r| <= max |c|, so f <= max|c|^n: refuse exponents that would overflow to inf.
  const double cmax = std::max({std::abs(cx), std::abs(cy), std::abs(cz)});
  if (cmax > 1.0 && n * std::log10(cmax) > kMaxLobeDecades)
    throw ArgumentError("model spec '" + spec() + "': lobe peak max(|cx|,|cy|,|cz|)^n = 10^" +
                        format_parameter(std::round(n * std::log10(cmax))) + " overflows; expected n log10(max|c|) <= " +
                        format_parameter(kMaxLobeDecades));
  const double a = azimuth_deg * M_PI / 180.0;
  Eigen::Matrix3d q;
  q << std::cos(a), std::sin(a), 0.0, -std::sin(a), std::cos(a), 0.0, 0.0, 0.0, 1.0;
  m_ = q.transpose() * Eigen::Vector3d(cx, cy, cz).asDiagonal() * q;
  m_ = 0.5 * (m_ + m_.transpose()).eval();  // exactly symmetric in floating point
}

double LafortuneModel::value(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const {
  // w_i^T M w_r written so that swapping w_i and w_r gives bitwise the same sum (exact reciprocity).
  const double base = m_(0, 0) * (wi.x() * wr.x()) + m_(1, 1) * (wi.y() * wr.y()) + m_(2, 2) * (wi.z() * wr.z()) +
                      m_(0, 1) * (wi.x() * wr.y() + wi.y() * wr.x()) + m_(0, 2) * (wi.x() * wr.z() + wi.z() * wr.x()) +
                      m_(1, 2) * (wi.y() * wr.z() + wi.z() * wr.y());
  return lobe(base, n_);
}

std::string LafortuneModel::spec() const {
  return format_model_spec("lafortune", {{"cx", format_parameter(cx_)},
                                         {"cy", format_parameter(cy_)},
                                         {"cz", format_parameter(cz_)},
                                         {"n", format_parameter(n_)},
                                         {"azimuth", format_parameter(azimuth_deg_)}});
}

}  // namespace icobrdf
