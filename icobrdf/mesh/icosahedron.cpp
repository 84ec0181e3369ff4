#include "icobrdf/mesh/icosahedron.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace icobrdf {
namespace {

// Coordinates of the unnormalized icosahedron are 0, +-1, +-phi; 1e-9 separates "zero" from the
// smallest non-zero coordinate (0.5) of any centroid or vertex with a wide margin.
constexpr double kZeroTol = 1e-9;

std::vector<Eigen::Vector3d> make_vertices() {
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> v;
  const double s[4][2] = {{1, 1}, {1, -1}, {-1, 1}, {-1, -1}};
  for (auto& p : s) v.emplace_back(0.0, p[0] * 1.0, p[1] * phi);
  for (auto& p : s) v.emplace_back(p[0] * 1.0, p[1] * phi, 0.0);
  for (auto& p : s) v.emplace_back(p[0] * phi, 0.0, p[1] * 1.0);
  for (auto& x : v) x.normalize();
  return v;
}

std::vector<std::array<int, 3>> make_faces() {
  const auto& v = icosahedron_vertices();
  // Adjacent vertices are the pairs at the minimum pairwise distance (the edge length).
  double dmin = 1e9;
  for (size_t i = 0; i < v.size(); ++i)
    for (size_t j = i + 1; j < v.size(); ++j) dmin = std::min(dmin, (v[i] - v[j]).norm());
  auto adj = [&](int a, int b) { return std::abs((v[a] - v[b]).norm() - dmin) < kZeroTol; };
  std::vector<std::array<int, 3>> f;
  for (int a = 0; a < 12; ++a)
    for (int b = a + 1; b < 12; ++b)
      for (int c = b + 1; c < 12; ++c)
        if (adj(a, b) && adj(b, c) && adj(a, c)) {
          const double orient = (v[b] - v[a]).cross(v[c] - v[a]).dot(v[a] + v[b] + v[c]);
          f.push_back(orient > 0 ? std::array<int, 3>{a, b, c} : std::array<int, 3>{a, c, b});
        }
  return f;
}

std::vector<HemiFace> make_hemi_faces() {
  const auto& v = icosahedron_vertices();
  std::vector<HemiFace> out;
  for (const auto& f : icosahedron_faces()) {
    const Eigen::Vector3d c = (v[f[0]] + v[f[1]] + v[f[2]]).normalized();
    if (c.z() < -kZeroTol) continue;
    HemiFace h;
    h.centre = c;
    h.bisected = std::abs(c.z()) < kZeroTol;
    // Rotate the cyclic order: bisected faces start at the equatorial vertex, whole ones at the lowest id.
    int start = 0;
    for (int k = 0; k < 3; ++k) {
      if (h.bisected ? std::abs(v[f[k]].z()) < kZeroTol : f[k] < f[start]) start = k;
    }
    for (int k = 0; k < 3; ++k) h.v[k] = f[(start + k) % 3];
    if (h.bisected) h.upper_corner = v[h.v[1]].z() > 0 ? 1 : 2;
    out.push_back(h);
  }
  auto azimuth = [](const Eigen::Vector3d& c) {
    double a = std::atan2(c.y(), c.x());
    return a < 0 ? a + 2 * M_PI : a;
  };
  std::sort(out.begin(), out.end(), [&](const HemiFace& a, const HemiFace& b) {
    if (std::abs(a.centre.z() - b.centre.z()) > kZeroTol) return a.centre.z() > b.centre.z();
    return azimuth(a.centre) < azimuth(b.centre) - kZeroTol;
  });
  return out;
}

}  // namespace

const std::vector<Eigen::Vector3d>& icosahedron_vertices() {
  static const std::vector<Eigen::Vector3d> v = make_vertices();
  return v;
}

const std::vector<std::array<int, 3>>& icosahedron_faces() {
  static const std::vector<std::array<int, 3>> f = make_faces();
  return f;
}

const std::vector<HemiFace>& hemi_icosahedron_faces() {
  static const std::vector<HemiFace> f = make_hemi_faces();
  return f;
}

std::array<Eigen::Vector3d, 3> hemi_face_corners(int face) {
  const auto& v = icosahedron_vertices();
  const HemiFace& f = hemi_icosahedron_faces().at(static_cast<size_t>(face));
  return {v[f.v[0]], v[f.v[1]], v[f.v[2]]};
}

}  // namespace icobrdf
