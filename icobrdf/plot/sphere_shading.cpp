#include "icobrdf/plot/sphere_shading.hpp"

#include <cmath>
#include <limits>

#include "icobrdf/core/support/error.hpp"

namespace icobrdf::plot {

Eigen::Vector3d light_direction(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

Eigen::Matrix3d sphere_local_frame(const Eigen::Vector3d& n) {
  Eigen::Vector3d t = Eigen::Vector3d::UnitY().cross(n);
  if (t.norm() < 1e-12) t = Eigen::Vector3d::UnitX();  // n = +-e_y: on the outline
  t.normalize();
  const Eigen::Vector3d b = n.cross(t);
  Eigen::Matrix3d f;
  f.row(0) = t.transpose();
  f.row(1) = b.transpose();
  f.row(2) = n.transpose();
  return f;
}

std::vector<Eigen::MatrixXd> shade_sphere(int size, int channels, const ReflectFunction& reflect,
                                          const AlbedoFunction& albedo, const SphereLighting& lighting) {
  if (size < 1) throw ArgumentError("sphere size " + std::to_string(size) + ": expected >= 1 pixel");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<Eigen::MatrixXd> out(static_cast<std::size_t>(channels), Eigen::MatrixXd::Constant(size, size, nan));
  std::vector<int> lit_pixel, all_pixel;
  std::vector<Eigen::Vector3d> lit_wi, lit_wo, all_wo;
  const Eigen::Vector3d v = Eigen::Vector3d::UnitZ();
  for (int i = 0; i < size; ++i)
    for (int j = 0; j < size; ++j) {
      const double x = -1.0 + (2.0 * j + 1.0) / size, y = 1.0 - (2.0 * i + 1.0) / size;
      const double r2 = x * x + y * y;
      if (r2 > 1.0) continue;
      const Eigen::Vector3d n(x, y, std::sqrt(1.0 - r2));
      const Eigen::Matrix3d f = sphere_local_frame(n);
      const Eigen::Vector3d wo = f * v, wi = f * lighting.light;
      for (auto& o : out) o(i, j) = 0.0;
      all_pixel.push_back(i * size + j);
      all_wo.push_back(wo);
      if (wi.z() > 0.0 && lighting.irradiance > 0.0) {
        lit_pixel.push_back(i * size + j);
        lit_wi.push_back(wi);
        lit_wo.push_back(wo);
      }
    }
  auto to_rows = [](const std::vector<Eigen::Vector3d>& d) {
    RowMatrix3d m(static_cast<Eigen::Index>(d.size()), 3);
    for (std::size_t k = 0; k < d.size(); ++k) m.row(static_cast<Eigen::Index>(k)) = d[k].transpose();
    return m;
  };
  if (!lit_pixel.empty()) {
    const Eigen::MatrixXd r = reflect(to_rows(lit_wi), to_rows(lit_wo));
    for (std::size_t k = 0; k < lit_pixel.size(); ++k)
      for (int c = 0; c < channels; ++c)
        out[c](lit_pixel[k] / size, lit_pixel[k] % size) += lighting.irradiance * r(static_cast<Eigen::Index>(k), c);
  }
  if (lighting.sky > 0.0 && !all_pixel.empty()) {
    const Eigen::MatrixXd a = albedo(to_rows(all_wo));
    for (std::size_t k = 0; k < all_pixel.size(); ++k)
      for (int c = 0; c < channels; ++c)
        out[c](all_pixel[k] / size, all_pixel[k] % size) += lighting.sky * a(static_cast<Eigen::Index>(k), c);
  }
  return out;
}

}  // namespace icobrdf::plot
