#include "icobrdf/core/models/ggx_vndf.hpp"

#include <algorithm>
#include <cmath>

#include "icobrdf/core/models/microfacet.hpp"

namespace icobrdf {

Eigen::Vector3d sample_ggx_visible_normal(const Eigen::Vector3d& wi, double alpha_x, double alpha_y, double u1,
                                          double u2) {
  // The view direction in the hemisphere configuration (alpha = 1): stretch by the widths.
  Eigen::Vector3d vh(alpha_x * wi.x(), alpha_y * wi.y(), std::max(wi.z(), 0.0));
  const double vn = vh.norm();
  vh = vn > 0.0 ? Eigen::Vector3d(vh / vn) : Eigen::Vector3d(0, 0, 1);
  // An orthonormal basis (t1, t2, vh); t1 = z x vh normalized, or x at normal incidence.
  const double lensq = vh.x() * vh.x() + vh.y() * vh.y();
  const Eigen::Vector3d t1 = lensq > 0.0 ? Eigen::Vector3d(-vh.y(), vh.x(), 0.0) / std::sqrt(lensq) : Eigen::Vector3d(1, 0, 0);
  const Eigen::Vector3d t2 = vh.cross(t1);
  // A uniform point on the unit disk, its second coordinate squeezed onto the projected visible half.
  const double r = std::sqrt(u1), phi = 2.0 * M_PI * u2;
  const double p1 = r * std::cos(phi);
  double p2 = r * std::sin(phi);
  const double s = 0.5 * (1.0 + vh.z());
  p2 = (1.0 - s) * std::sqrt(std::max(0.0, 1.0 - p1 * p1)) + s * p2;
  const Eigen::Vector3d nh = p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0, 1.0 - p1 * p1 - p2 * p2)) * vh;
  // Back to the ellipsoid configuration.
  Eigen::Vector3d h(alpha_x * nh.x(), alpha_y * nh.y(), std::max(nh.z(), 0.0));
  const double hn = h.norm();
  return hn > 0.0 ? Eigen::Vector3d(h / hn) : Eigen::Vector3d(0, 0, 1);
}

double ggx_visible_normal_pdf(const Eigen::Vector3d& wi, const Eigen::Vector3d& h, double alpha_x, double alpha_y) {
  const double c = wi.dot(h);
  if (!(h.z() > 0.0) || !(c > 0.0)) return 0.0;
  const double denominator = std::max(wi.z(), 0.0) + smith_z_lambda(MicrofacetDistribution::Ggx, wi, alpha_x, alpha_y);
  if (!(denominator > 0.0)) return 0.0;
  return c * microfacet_d(MicrofacetDistribution::Ggx, h, alpha_x, alpha_y) / denominator;
}

}  // namespace icobrdf
