#include "icobrdf/core/grid/grid.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "icobrdf/core/support/error.hpp"

namespace icobrdf {
namespace {

constexpr GridKind kGridKinds[] = {GridKind::Custom, GridKind::EqualArea, GridKind::Geodesic, GridKind::PolarGauss, GridKind::LatLong};

// Cubature weights are sums of exact per-point weights; a relative 1e-12 allows the rounding of summing
// thousands of terms while still catching any wrong weight.
constexpr double kWeightSumRelTol = 1e-12;
// Unit vectors are produced by normalization; 1e-12 is far above its rounding and far below any real error.
constexpr double kUnitTol = 1e-12;

[[noreturn]] void fail(const std::string& what) { throw std::invalid_argument("invalid grid: " + what); }

void check_permutation(const Eigen::VectorXi& p, int n, const char* name) {
  if (p.size() == 0) return;
  if (p.size() != n) fail(std::string(name) + " has " + std::to_string(p.size()) + " entries, expected " + std::to_string(n));
  std::vector<char> seen(n, 0);
  for (int i = 0; i < n; ++i) {
    if (p[i] < 0 || p[i] >= n || seen[p[i]]) fail(std::string(name) + " is not a permutation (entry " + std::to_string(i) + ")");
    seen[p[i]] = 1;
  }
}

void check_units(const RowMatrix3d& m, const char* name) {
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    const double norm = m.row(i).norm();
    if (std::abs(norm - 1.0) > kUnitTol) fail(std::string(name) + " row " + std::to_string(i) + " has norm " + std::to_string(norm) + ", expected 1");
    if (m(i, 2) < -kUnitTol) fail(std::string(name) + " row " + std::to_string(i) + " is below the horizon (z = " + std::to_string(m(i, 2)) + ")");
  }
}

}  // namespace

const char* to_string(GridKind kind) {
  switch (kind) {
    case GridKind::Custom: return "custom";
    case GridKind::EqualArea: return "equal-area";
    case GridKind::Geodesic: return "geodesic";
    case GridKind::PolarGauss: return "polar-gauss";
    case GridKind::LatLong: return "lat-long";
  }
  return "custom";
}

GridKind parse_grid_kind(const std::string& name) {
  std::string names;
  for (GridKind k : kGridKinds) {
    if (name == to_string(k)) return k;
    names += std::string(names.empty() ? "" : ", ") + to_string(k);
  }
  throw ArgumentError("unknown grid kind '" + name + "': expected one of " + names);
}

Grid cells_in_order(const Grid& g, const std::vector<int>& perm) {
  Grid r;
  r.kind = g.kind;
  r.level = g.level;
  r.cubature_degree = g.cubature_degree;
  const int cells = static_cast<int>(perm.size());
  r.directions.resize(cells, 3);
  r.solid_angles.resize(cells);
  r.cubature_offsets.assign(1, 0);
  Eigen::Index points = 0;
  for (const int c : perm) {
    if (c < 0 || c >= g.cells())
      throw ArgumentError("cells in order: cell " + std::to_string(c) + " outside the grid's " + std::to_string(g.cells()));
    points += g.cubature_offsets[static_cast<size_t>(c) + 1] - g.cubature_offsets[static_cast<size_t>(c)];
  }
  r.cubature_points.resize(points, 3);
  r.cubature_weights.resize(points);
  Eigen::Index q = 0;
  for (int k = 0; k < cells; ++k) {
    const int c = perm[static_cast<size_t>(k)];
    r.directions.row(k) = g.directions.row(c);
    r.solid_angles[k] = g.solid_angles[c];
    const auto b = g.cubature_offsets[static_cast<size_t>(c)], e = g.cubature_offsets[static_cast<size_t>(c) + 1];
    r.cubature_points.middleRows(q, e - b) = g.cubature_points.middleRows(b, e - b);
    r.cubature_weights.segment(q, e - b) = g.cubature_weights.segment(b, e - b);
    q += e - b;
    r.cubature_offsets.push_back(q);
  }
  return r;
}


Grid with_centre_cubature(const Grid& grid) {
  Grid g = grid;
  const int n = g.cells();
  g.cubature_offsets.resize(static_cast<size_t>(n) + 1);
  for (int c = 0; c <= n; ++c) g.cubature_offsets[static_cast<size_t>(c)] = c;
  g.cubature_points = g.directions;
  g.cubature_weights = g.solid_angles;
  g.cubature_degree = 1;
  return g;
}

void validate(const Grid& g) {
  const int n = g.cells();
  if (n == 0) fail("no cells");
  if (g.directions.rows() != n) fail("directions has " + std::to_string(g.directions.rows()) + " rows, expected " + std::to_string(n));
  check_units(g.directions, "directions");
  for (int c = 0; c < n; ++c)
    if (!(g.solid_angles[c] > 0.0)) fail("solid angle of cell " + std::to_string(c) + " is not positive");
  if (g.cubature_offsets.size() != static_cast<size_t>(n) + 1) fail("cubature_offsets has " + std::to_string(g.cubature_offsets.size()) + " entries, expected " + std::to_string(n + 1));
  if (g.cubature_offsets.front() != 0 || g.cubature_offsets.back() != g.cubature_points.rows() || g.cubature_weights.size() != g.cubature_points.rows())
    fail("cubature offsets, points and weights disagree in size");
  check_units(g.cubature_points, "cubature_points");
  for (int c = 0; c < n; ++c) {
    const auto b = g.cubature_offsets[c], e = g.cubature_offsets[c + 1];
    if (e <= b) fail("cell " + std::to_string(c) + " has no cubature points");
    const double s = g.cubature_weights.segment(b, e - b).sum();
    if (std::abs(s - g.solid_angles[c]) > kWeightSumRelTol * g.solid_angles[c])
      fail("cubature weights of cell " + std::to_string(c) + " sum to " + std::to_string(s) + ", expected its solid angle " + std::to_string(g.solid_angles[c]));
  }
  if (g.faces.rows() != 0 && g.faces.rows() != n) fail("faces has " + std::to_string(g.faces.rows()) + " rows, expected " + std::to_string(n));
  if (g.neighbours.rows() != 0 && g.neighbours.rows() != n) fail("neighbours has wrong row count");
  if (!g.is_half.empty() && g.is_half.size() != static_cast<size_t>(n)) fail("is_half has wrong size");
  check_units(g.vertices, "vertices");
  for (Eigen::Index c = 0; c < g.faces.rows(); ++c)
    for (int k = 0; k < 3; ++k)
      if (g.faces(c, k) < 0 || g.faces(c, k) >= g.vertices.rows()) fail("face " + std::to_string(c) + " names a missing vertex");
  check_permutation(g.rotate_pi, n, "rotate_pi");
  check_permutation(g.mirror_xz, n, "mirror_xz");
  check_permutation(g.mirror_yz, n, "mirror_yz");
}

}  // namespace icobrdf
