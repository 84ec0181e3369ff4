#include "icobrdf/core/models/kernel_models.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace icobrdf {
namespace {

// Li kernels' crown shape (MODIS): height to crown radius h/b = 2, crown radius ratio b/r = 1.
constexpr double kLiHeightOverB = 2.0;
constexpr double kLiBOverR = 1.0;

// The angles of a pair as remote sensing writes them, from unit vectors on or above the horizon. The
// tangent-plane slopes s = (x, y) / cos(theta) carry tan(theta) and the azimuth together: D^2 = |s_i - s_r|^2 and
// tan(sza) tan(vza) sin(raa) = s_i x s_r need no cosine of raa (no cancellation at the hot spot).
struct PairAngles {
  double cos_i, cos_r;      // cosines of sza and vza, floored at kGrazingCosFloor (the kernels divide by them)
  double tan_i, tan_r;      // |s_i|, |s_r| (with the floored cosines)
  double slope_dot;         // s_i . s_r = tan(sza) tan(vza) cos(raa)
  double d2;                // |s_i - s_r|^2 = D^2
  double cross;             // s_i x s_r = tan(sza) tan(vza) sin(raa) (signed; the kernels square it)
  double cos_raa;           // cosine of the relative azimuth (1 when a direction is the normal)
  double cos_xi;            // phase angle: w_i . w_r
};

// The pair's angles from its two directions taken in a canonical order (lexicographic in z, x, y): every
// formula is symmetric in the two, and this makes the rounding symmetric too, so exchanging the directions
// gives the same bits whatever the compiler fuses into multiply-adds.
PairAngles angles_of(const Eigen::Vector3d& first, const Eigen::Vector3d& second) {
  const bool keep = std::make_tuple(first.z(), first.x(), first.y()) <= std::make_tuple(second.z(), second.x(), second.y());
  const Eigen::Vector3d& wi = keep ? first : second;
  const Eigen::Vector3d& wr = keep ? second : first;
  PairAngles a;
  a.cos_i = std::max(std::clamp(wi.z(), 0.0, 1.0), kGrazingCosFloor);
  a.cos_r = std::max(std::clamp(wr.z(), 0.0, 1.0), kGrazingCosFloor);
  const double sxi = wi.x() / a.cos_i, syi = wi.y() / a.cos_i, sxr = wr.x() / a.cos_r, syr = wr.y() / a.cos_r;
  a.tan_i = std::hypot(sxi, syi);
  a.tan_r = std::hypot(sxr, syr);
  a.slope_dot = sxi * sxr + syi * syr;
  a.d2 = (sxi - sxr) * (sxi - sxr) + (syi - syr) * (syi - syr);
  a.cross = sxi * syr - syi * sxr;
  a.cos_raa = a.tan_i > 0.0 && a.tan_r > 0.0 ? std::clamp(a.slope_dot / (a.tan_i * a.tan_r), -1.0, 1.0) : 1.0;
  a.cos_xi = std::clamp(wi.dot(wr), -1.0, 1.0);
  return a;
}

}  // namespace

double ross_kernel(VolumeKernel kind, const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) {
  const PairAngles a = angles_of(wi, wr);
  const double xi = std::acos(a.cos_xi);
  const double num = (M_PI / 2 - xi) * a.cos_xi + std::sin(xi);
  if (kind == VolumeKernel::RossThick) return num / (a.cos_i + a.cos_r) - M_PI / 4;
  return num / (a.cos_i * a.cos_r) - M_PI / 2;
}

double li_kernel(GeometricKernel kind, const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) {
  const PairAngles a = angles_of(wi, wr);
  // Primed angles: tan(theta') = (b/r) tan(theta), so the slopes scale by b/r.
  const double br2 = kLiBOverR * kLiBOverR;
  const double ti = kLiBOverR * a.tan_i, tr = kLiBOverR * a.tan_r;
  const double sec_i = std::sqrt(1.0 + ti * ti), sec_r = std::sqrt(1.0 + tr * tr);
  const double cos_xi = (1.0 + br2 * a.slope_dot) / (sec_i * sec_r);  // cos(xi'): primed directions' dot product
  const double cross = br2 * a.cross;
  const double cos_t = std::clamp(kLiHeightOverB * std::sqrt(br2 * a.d2 + cross * cross) / (sec_i + sec_r), -1.0, 1.0);
  const double t = std::acos(cos_t);
  const double overlap = (t - std::sin(t) * cos_t) * (sec_i + sec_r) / M_PI;
  // sec_i + sec_r summed first: exchanging the directions gives the same bits.
  if (kind == GeometricKernel::LiSparseR) return overlap - (sec_i + sec_r) + 0.5 * (1.0 + cos_xi) * (sec_i * sec_r);
  return (1.0 + cos_xi) * (sec_i * sec_r) / (sec_i + sec_r - overlap) - 2.0;
}

double RossLiModel::value(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const {
  return (iso_ + vol_ * ross_kernel(volume_, wi, wr) + geo_ * li_kernel(geometric_, wi, wr)) / M_PI;
}

std::string RossLiModel::spec() const {
  return format_model_spec("ross-li", {{"iso", format_parameter(iso_)},
                                       {"vol", format_parameter(vol_)},
                                       {"geo", format_parameter(geo_)},
                                       {"volume", volume_ == VolumeKernel::RossThick ? "thick" : "thin"},
                                       {"geometric", geometric_ == GeometricKernel::LiSparseR ? "sparse" : "dense"}});
}

double RpvModel::value(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const {
  const PairAngles a = angles_of(wi, wr);
  const double m = rho0_ * std::pow(a.cos_i * a.cos_r, k_ - 1.0) / std::pow(a.cos_i + a.cos_r, 1.0 - k_);
  const double hg = (1.0 - theta_ * theta_) / std::pow(1.0 + 2.0 * theta_ * a.cos_xi + theta_ * theta_, 1.5);
  const double g = std::sqrt(a.d2);
  return m * hg * (1.0 + (1.0 - rhoc_) / (1.0 + g)) / M_PI;
}

std::string RpvModel::spec() const {
  return format_model_spec("rpv", {{"rho0", format_parameter(rho0_)},
                                   {"k", format_parameter(k_)},
                                   {"theta", format_parameter(theta_)},
                                   {"rhoc", format_parameter(rhoc_)}});
}

double WalthallModel::value(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const {
  const PairAngles a = angles_of(wi, wr);
  const double ti = std::acos(std::clamp(wi.z(), 0.0, 1.0)), tr = std::acos(std::clamp(wr.z(), 0.0, 1.0));
  // Grouped so that exchanging the directions gives the same bits.
  const double brf = a_ * (ti * ti + tr * tr) + b_ * ((ti * ti) * (tr * tr)) + c_ * (ti * tr) * a.cos_raa + d_;
  return brf / M_PI;
}

std::string WalthallModel::spec() const {
  return format_model_spec("walthall", {{"a", format_parameter(a_)},
                                        {"b", format_parameter(b_)},
                                        {"c", format_parameter(c_)},
                                        {"d", format_parameter(d_)}});
}

}  // namespace icobrdf
