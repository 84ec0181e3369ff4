#include "icobrdf/plot/disk_raster.hpp"

#include <limits>

#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/basis/lambert_map.hpp"

namespace icobrdf::plot {

Eigen::Vector2d disk_pixel_centre(int size, int row, int col) {
  return {-1.0 + (2.0 * col + 1.0) / size, 1.0 - (2.0 * row + 1.0) / size};
}

DiskSamples disk_samples(int size) {
  DiskSamples s;
  s.size = size;
  std::vector<Eigen::Vector3d> dirs;
  for (int i = 0; i < size; ++i)
    for (int j = 0; j < size; ++j) {
      const Eigen::Vector2d p = disk_pixel_centre(size, i, j);
      if (p.squaredNorm() > 1.0) continue;
      dirs.push_back(lambert_from_disk(p));
      s.pixel.push_back(i * size + j);
    }
  s.directions.resize(static_cast<Eigen::Index>(dirs.size()), 3);
  for (std::size_t k = 0; k < dirs.size(); ++k) s.directions.row(static_cast<Eigen::Index>(k)) = dirs[k].transpose();
  return s;
}

Eigen::MatrixXd disk_raster(const DiskSamples& s, const Eigen::VectorXd& values) {
  Eigen::MatrixXd r = Eigen::MatrixXd::Constant(s.size, s.size, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t k = 0; k < s.pixel.size(); ++k) r(s.pixel[k] / s.size, s.pixel[k] % s.size) = values[static_cast<Eigen::Index>(k)];
  return r;
}

Eigen::MatrixXd disk_basis(const DiskSamples& s, int order) { return hemisphere_basis_matrix(order, s.directions); }

}  // namespace icobrdf::plot
