#include "icobrdf/mesh/cubature_symmetry.hpp"

#include <array>
#include <string>
#include <vector>

#include "icobrdf/core/support/error.hpp"

namespace icobrdf {
namespace {

// The group: identity, rotation by pi about z, y -> -y, x -> -x (as sign flips of x and y).
constexpr std::array<std::array<double, 2>, 4> kSigns{{{1, 1}, {-1, -1}, {1, -1}, {-1, 1}}};

Eigen::Vector3d apply(int gamma, const Eigen::Vector3d& p) { return {kSigns[gamma][0] * p.x(), kSigns[gamma][1] * p.y(), p.z()}; }

}  // namespace

void make_cubature_equivariant(Grid& g) {
  const int n = g.cells();
  if (g.rotate_pi.size() != n || g.mirror_xz.size() != n || g.mirror_yz.size() != n)
    throw ArgumentError("equivariant cubature: grid of kind '" + std::string(to_string(g.kind)) + "' lacks its symmetry maps");
  auto image = [&](int gamma, int c) {
    switch (gamma) {
      case 1: return g.rotate_pi[c];
      case 2: return g.mirror_xz[c];
      case 3: return g.mirror_yz[c];
      default: return c;
    }
  };
  std::vector<std::vector<Eigen::Vector3d>> pts(static_cast<size_t>(n));
  std::vector<std::vector<double>> wts(static_cast<size_t>(n));
  RowMatrix3d dirs(n, 3);
  std::vector<char> done(static_cast<size_t>(n), 0);
  for (int c = 0; c < n; ++c) {
    if (done[c]) continue;
    std::vector<int> stab;
    for (int gamma = 0; gamma < 4; ++gamma)
      if (image(gamma, c) == c) stab.push_back(gamma);
    // The representative's rule, averaged over its stabilizer.
    std::vector<Eigen::Vector3d> rp;
    std::vector<double> rw;
    Eigen::Vector3d dir = Eigen::Vector3d::Zero();
    for (int gamma : stab) {
      for (auto q = g.cubature_offsets[c]; q < g.cubature_offsets[c + 1]; ++q) {
        rp.push_back(apply(gamma, g.cubature_points.row(q).transpose()));
        rw.push_back(g.cubature_weights[q] / static_cast<double>(stab.size()));
      }
      dir += apply(gamma, g.directions.row(c).transpose());
    }
    dir.normalize();
    for (int gamma = 0; gamma < 4; ++gamma) {
      const int t = image(gamma, c);
      if (done[t]) continue;
      done[t] = 1;
      auto& tp = pts[static_cast<size_t>(t)];
      tp.reserve(rp.size());
      for (const auto& p : rp) tp.push_back(apply(gamma, p));
      wts[static_cast<size_t>(t)] = rw;
      dirs.row(t) = apply(gamma, dir).transpose();
    }
  }
  std::int64_t total = 0;
  for (int c = 0; c < n; ++c) total += static_cast<std::int64_t>(pts[c].size());
  g.cubature_points.resize(total, 3);
  g.cubature_weights.resize(total);
  std::int64_t row = 0;
  for (int c = 0; c < n; ++c) {
    g.cubature_offsets[static_cast<size_t>(c)] = row;
    for (size_t k = 0; k < pts[c].size(); ++k, ++row) {
      g.cubature_points.row(row) = pts[c][k].transpose();
      g.cubature_weights[row] = wts[c][k];
    }
  }
  g.cubature_offsets[static_cast<size_t>(n)] = row;
  g.directions = dirs;
}

}  // namespace icobrdf
