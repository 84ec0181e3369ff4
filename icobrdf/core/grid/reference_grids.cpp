#include "icobrdf/core/grid/reference_grids.hpp"

#include <cmath>
#include <string>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/grid/gauss_legendre.hpp"

namespace icobrdf {
namespace {

Eigen::Vector3d from_cos_phi(double c, double phi) {
  const double s = std::sqrt(std::max(0.0, (1.0 - c) * (1.0 + c)));
  return {s * std::cos(phi), s * std::sin(phi), c};
}

// Azimuthal index maps for sectors/nodes indexed by m around the circle with n_phi even.
void set_symmetries(Grid& g, int rings, int n_phi, bool sectors) {
  if (n_phi % 2) return;
  const int n = rings * n_phi;
  g.rotate_pi.resize(n);
  g.mirror_xz.resize(n);
  g.mirror_yz.resize(n);
  for (int k = 0; k < rings; ++k)
    for (int m = 0; m < n_phi; ++m) {
      const int c = k * n_phi + m;
      g.rotate_pi[c] = k * n_phi + (m + n_phi / 2) % n_phi;
      // Nodes at phi_m = 2 pi m / n: y -> -y maps m to -m, x -> -x maps m to n/2 - m.
      // Sectors [2 pi m / n, 2 pi (m+1) / n]: y -> -y maps m to n - 1 - m, x -> -x to n/2 - 1 - m.
      const int s = sectors ? 1 : 0;
      g.mirror_xz[c] = k * n_phi + ((n_phi - m - s) % n_phi + n_phi) % n_phi;
      g.mirror_yz[c] = k * n_phi + ((n_phi / 2 - m - s) % n_phi + n_phi) % n_phi;
    }
}

}  // namespace

Grid build_polar_gauss_grid(int rings, int n_phi) {
  if (rings < 1 || n_phi < 1)
    throw ArgumentError("polar Gauss grid: rings and n_phi expected >= 1, got " + std::to_string(rings) + " and " + std::to_string(n_phi));
  const auto gl = gauss_legendre(rings, 0.0, 1.0);
  Grid g;
  g.kind = GridKind::PolarGauss;
  g.level = -1;
  const int n = rings * n_phi;
  g.directions.resize(n, 3);
  g.solid_angles.resize(n);
  g.cubature_offsets.resize(static_cast<size_t>(n) + 1);
  for (int k = 0; k < rings; ++k)
    for (int m = 0; m < n_phi; ++m) {
      const int c = k * n_phi + m;
      g.directions.row(c) = from_cos_phi(1.0 - gl.nodes[k], 2.0 * M_PI * m / n_phi).transpose();
      g.solid_angles[c] = gl.weights[k] * 2.0 * M_PI / n_phi;
      g.cubature_offsets[static_cast<size_t>(c)] = c;
    }
  g.cubature_offsets[static_cast<size_t>(n)] = n;
  g.cubature_points = g.directions;
  g.cubature_weights = g.solid_angles;
  g.cubature_degree = 2 * rings - 1;
  set_symmetries(g, rings, n_phi, false);
  return g;
}

Grid build_lat_long_grid(int n_theta, int n_phi, int points) {
  if (n_theta < 1 || n_phi < 1 || points < 1)
    throw ArgumentError("lat-long grid: n_theta, n_phi and points expected >= 1, got " + std::to_string(n_theta) + ", " +
                        std::to_string(n_phi) + ", " + std::to_string(points));
  Grid g;
  g.kind = GridKind::LatLong;
  g.level = -1;
  const int n = n_theta * n_phi, pp = points * points;
  g.directions.resize(n, 3);
  g.solid_angles.resize(n);
  g.cubature_offsets.resize(static_cast<size_t>(n) + 1);
  g.cubature_points.resize(static_cast<Eigen::Index>(n) * pp, 3);
  g.cubature_weights.resize(static_cast<Eigen::Index>(n) * pp);
  const double dphi = 2.0 * M_PI / n_phi;
  for (int k = 0; k < n_theta; ++k) {
    const double t0 = 0.5 * M_PI * k / n_theta, t1 = 0.5 * M_PI * (k + 1) / n_theta;
    const double c0 = std::cos(t1), c1 = std::cos(t0);  // cos theta ascending
    const auto gc = gauss_legendre(points, c0, c1);
    for (int m = 0; m < n_phi; ++m) {
      const int c = k * n_phi + m;
      const auto gp = gauss_legendre(points, m * dphi, (m + 1) * dphi);
      g.solid_angles[c] = (c1 - c0) * dphi;
      g.directions.row(c) = from_cos_phi(std::cos(0.5 * (t0 + t1)), (m + 0.5) * dphi).transpose();
      const Eigen::Index base = static_cast<Eigen::Index>(c) * pp;
      g.cubature_offsets[static_cast<size_t>(c)] = base;
      for (int a = 0; a < points; ++a)
        for (int b = 0; b < points; ++b) {
          g.cubature_points.row(base + a * points + b) = from_cos_phi(gc.nodes[a], gp.nodes[b]).transpose();
          g.cubature_weights[base + a * points + b] = gc.weights[a] * gp.weights[b];
        }
    }
  }
  g.cubature_offsets[static_cast<size_t>(n)] = static_cast<Eigen::Index>(n) * pp;
  g.cubature_degree = 2 * points - 1;
  set_symmetries(g, n_theta, n_phi, true);
  return g;
}

}  // namespace icobrdf
