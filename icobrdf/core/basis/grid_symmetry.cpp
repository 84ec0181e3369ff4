#include "icobrdf/core/basis/grid_symmetry.hpp"

#include <algorithm>
#include <cmath>

#include "icobrdf/core/basis/hemisphere_basis.hpp"

namespace icobrdf {

int D2Map::sign(int l) const {
  const int parity = (std::abs(l) % 2 == 0) ? 1 : -1;
  if (sx < 0 && sy < 0) return parity;  // rotation by pi: phi -> phi + pi
  if (sy < 0) return l < 0 ? -1 : 1;    // y -> -y: phi -> -phi
  return l < 0 ? -parity : parity;      // x -> -x: phi -> pi - phi
}

int d2_class(int j) {
  const int l = ansi_to_nl(j).l;
  return (std::abs(l) % 2) + (l < 0 ? 2 : 0);
}

bool has_d2_maps(const Grid& g) {
  return g.rotate_pi.size() == g.cells() && g.mirror_xz.size() == g.cells() && g.mirror_yz.size() == g.cells();
}

std::vector<D2Map> d2_maps(const Grid& g) {
  return {{&g.rotate_pi, -1.0, -1.0}, {&g.mirror_xz, 1.0, -1.0}, {&g.mirror_yz, -1.0, 1.0}};
}

std::vector<D2Representative> d2_representatives(const Grid& g) {
  std::vector<D2Representative> out;
  for (int c = 0; c < g.cells(); ++c) {
    const int images[3] = {g.rotate_pi[c], g.mirror_xz[c], g.mirror_yz[c]};
    if (*std::min_element(images, images + 3) < c) continue;  // not the orbit's smallest cell
    int stabilizer = 1;
    for (int m : images) stabilizer += m == c ? 1 : 0;
    out.push_back({c, 1.0 / stabilizer});
  }
  return out;
}

namespace {

bool near(double a, double b, double scale) { return std::abs(a - b) <= kMirroredCubatureRelTol * scale; }

}  // namespace

bool cubature_is_image(const Grid& g, const D2Map& s, int c, int t, bool centres) {
  if (t < 0 || t >= g.cells() || !near(g.solid_angles[t], g.solid_angles[c], g.solid_angles[c])) return false;
  if (centres)
    return near(s.sx * g.directions(c, 0), g.directions(t, 0), 1.0) && near(s.sy * g.directions(c, 1), g.directions(t, 1), 1.0) &&
           near(g.directions(c, 2), g.directions(t, 2), 1.0);
  const auto b = g.cubature_offsets[static_cast<size_t>(c)], e = g.cubature_offsets[static_cast<size_t>(c) + 1];
  const auto tb = g.cubature_offsets[static_cast<size_t>(t)], te = g.cubature_offsets[static_cast<size_t>(t) + 1];
  if (e - b != te - tb) return false;
  for (auto p = b; p < e; ++p) {
    bool found = false;
    for (auto q = tb; q < te && !found; ++q)
      found = near(s.sx * g.cubature_points(p, 0), g.cubature_points(q, 0), 1.0) &&
              near(s.sy * g.cubature_points(p, 1), g.cubature_points(q, 1), 1.0) &&
              near(g.cubature_points(p, 2), g.cubature_points(q, 2), 1.0) &&
              near(g.cubature_weights[p], g.cubature_weights[q], g.cubature_weights[p]);
    if (!found) return false;
  }
  return true;
}

bool sampling_is_d2_symmetric(const Grid& g, bool centres) {
  if (!has_d2_maps(g)) return false;
  for (const auto& s : d2_maps(g))
    for (int c = 0; c < g.cells(); ++c)
      if (!cubature_is_image(g, s, c, (*s.cells)[c], centres)) return false;
  return true;
}

bool rows_are_d2_equivariant(const Grid& g, const Eigen::MatrixXd& m, double tol) {
  if (!has_d2_maps(g) || m.rows() != g.cells()) return false;
  const double bound = tol * std::max(1e-300, m.cwiseAbs().maxCoeff());
  for (const auto& s : d2_maps(g)) {
    for (int c = 0; c < g.cells(); ++c)
      if ((*s.cells)[c] < 0 || (*s.cells)[c] >= g.cells()) return false;
    bool ok = true;
#pragma omp parallel for schedule(static) reduction(&& : ok) if (m.size() > 100000)
    for (Eigen::Index a = 0; a < m.cols(); ++a) {
      const double sign = s.sign(ansi_to_nl(static_cast<int>(a)).l);
      const double* col = m.col(a).data();
      const int* map = s.cells->data();
      double worst = 0.0;
      for (int c = 0; c < g.cells(); ++c) worst = std::max(worst, std::abs(col[map[c]] - sign * col[c]));
      ok = ok && worst <= bound;
    }
    if (!ok) return false;
  }
  return true;
}

Eigen::MatrixXd d2_average(const Eigen::MatrixXd& x) {
  std::vector<int> cls(static_cast<size_t>(x.rows()));
  for (Eigen::Index a = 0; a < x.rows(); ++a) cls[static_cast<size_t>(a)] = d2_class(static_cast<int>(a));
  Eigen::MatrixXd out(x.rows(), x.cols());
  for (Eigen::Index b = 0; b < x.cols(); ++b)
    for (Eigen::Index a = 0; a < x.rows(); ++a) out(a, b) = cls[static_cast<size_t>(a)] == cls[static_cast<size_t>(b)] ? 4.0 * x(a, b) : 0.0;
  return out;
}

}  // namespace icobrdf
