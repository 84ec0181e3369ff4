#pragma once
// The (theta_h, theta_d) image of a BRDF, as MERL's and Disney's BRDF explorers show measured materials:
// f at half-vector polar angle theta_h (across, 0..90 degrees) and difference angle theta_d (down the
// picture from 0 at the top, 0..90 degrees), at one difference azimuth phi_d (default 90 degrees, MERL's
// pictures; 0 puts w_i and w_o in the plane of h and the normal, where the grazing retro and specular
// directions lie) and half-vector azimuth phi_h = 0 (Rusinkiewicz's coordinates: h = (sin theta_h, 0, cos theta_h); w_i is d =
// (sin theta_d cos phi_d, sin theta_d sin phi_d, cos theta_d) turned by theta_h about y, w_o its mirror about h).
// Pairs with either direction below the horizon are left blank. Channel mean on the sequential map, linear
// or (`log`) over kDefaultDecades decades (the specular peak and the diffuse floor in one picture). The
// scale's top is the 95th percentile of the values: the grazing rows (theta_d -> 90 degrees), where f grows
// as 1 / (cos theta_i cos theta_o), saturate instead of leaving the rest of the picture dark.
#include <string>

#include "icobrdf/plot/plots.hpp"
#include "icobrdf/plot/value_scale.hpp"

namespace icobrdf::plot {

struct HalfDiffFigure {
  PanelRect image;    // the size x size raster: column j at theta_h = 90 (j + 0.5) / size degrees, row i at theta_d likewise
  ValueScale scale;
  int width = 0, height = 0;
};
inline constexpr int kHalfDiffSize = 240;  // default image side in pixels
inline constexpr double kDefaultPhiD = 1.5707963267948966;  // 90 degrees, radians
// The directions of pixel (row i, column j) of a size x size image at difference azimuth phi_d (radians): w_i
// and w_o (unit, z up).
std::pair<Eigen::Vector3d, Eigen::Vector3d> half_diff_directions(int size, int i, int j, double phi_d = kDefaultPhiD);
HalfDiffFigure plot_half_diff(const std::string& label, const PairFunction& values, bool log, const std::string& path, int size = kHalfDiffSize,
                              double phi_d = kDefaultPhiD);

}  // namespace icobrdf::plot
