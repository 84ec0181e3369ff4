#pragma once
// A sphere of a material seen by an orthographic camera, lit by a distant light and a uniform sky.
//
// Camera frame: x to the right of the picture, y up, z towards the viewer. The camera looks along -z; the
// view direction (towards the viewer) is v = (0, 0, 1) everywhere. Pixel (row i, column j) of a size x size
// raster has its centre at (x, y) = (-1 + (2j+1)/size, 1 - (2i+1)/size); inside the unit circle it sees the
// sphere point with normal n = (x, y, sqrt(1 - x^2 - y^2)).
// Local frame of the BRDF at n (normal +z of the BRDF): tangent t = (e_y x n) / |e_y x n|, bitangent
// b = n x t, i.e. t runs along the circles of latitude of a globe whose axis is the picture's vertical y
// (t = +x at the centre of the picture); a direction w has local coordinates (w.t, w.b, w.n).
// Degenerate only at n = +-e_y, on the outline, where a fixed tangent is used.
//
// Radiance towards the viewer, per channel:
//   L = E f(w_i, v) cos(theta_i) [cos(theta_i) > 0]  +  L_sky a(v),   a(v) = integral f(w, v) cos(theta) dOmega_w,
// with w_i the light direction and E its irradiance at normal incidence. With E = pi a Lambertian of
// albedo rho facing the light has L = rho; the uniform sky of radiance L_sky adds L_sky times the
// directional albedo (reciprocity). Pixels outside the sphere are NaN.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <functional>
#include <vector>

#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf::plot {

// rows x channels: the reflected part f(w_i, w_o) cos(theta_i) at local direction pairs (theta_i < 90 deg).
using ReflectFunction = std::function<Eigen::MatrixXd(const RowMatrix3d& wi, const RowMatrix3d& wo)>;
// rows x channels: directional albedo at local view directions.
using AlbedoFunction = std::function<Eigen::MatrixXd(const RowMatrix3d& wo)>;

struct SphereLighting {
  Eigen::Vector3d light{0.0, 0.0, 1.0};  // unit vector towards the light, camera frame
  double irradiance = 3.14159265358979323846;  // E at normal incidence
  double sky = 0.0;                            // sky radiance L_sky (0: no sky)
};

// Light direction (camera frame) from theta (from the viewing axis z) and phi (counter-clockwise from +x), radians.
Eigen::Vector3d light_direction(double theta, double phi);

// The local frame (t, b, n) at a sphere normal n, as rows of a 3 x 3 matrix (local = frame * world).
Eigen::Matrix3d sphere_local_frame(const Eigen::Vector3d& n);

// One size x size raster per channel; `albedo` is only called when lighting.sky > 0.
std::vector<Eigen::MatrixXd> shade_sphere(int size, int channels, const ReflectFunction& reflect,
                                          const AlbedoFunction& albedo, const SphereLighting& lighting);

}  // namespace icobrdf::plot
