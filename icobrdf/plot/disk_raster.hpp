#pragma once
// Rasters of functions on the hemisphere seen from above through the Lambert map (icobrdf/core/basis/lambert_map.hpp).
//
// A size x size raster covers the square [-1, 1]^2 around the unit disk; pixel (row i, column j) has its
// centre at the disk point x = -1 + (2 j + 1) / size, y = 1 - (2 i + 1) / size: +x to the right, +y up,
// i.e. the hemisphere seen from above (from +z) with azimuth phi counter-clockwise from the right.
// Pixels whose centre lies outside the disk (|p| > 1) carry NaN. Equal areas of the picture are equal
// solid angles (dOmega = 2 dA).
#include <Eigen/Core>

#include <vector>

#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf::plot {

Eigen::Vector2d disk_pixel_centre(int size, int row, int col);

// The directions of the pixels inside the disk and where they go.
struct DiskSamples {
  int size = 0;
  RowMatrix3d directions;    // inside pixels x 3, unit vectors (lambert_from_disk of the centres)
  std::vector<int> pixel;    // row * size + col of each direction
};
DiskSamples disk_samples(int size);

// size x size raster with values[k] at pixel[k], NaN elsewhere.
Eigen::MatrixXd disk_raster(const DiskSamples& s, const Eigen::VectorXd& values);

// Every K_j (j < (N+1)(N+2)/2) on the disk: inside pixels x modes.
Eigen::MatrixXd disk_basis(const DiskSamples& s, int order);

}  // namespace icobrdf::plot
