#include "icobrdf/io/grid_file.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "icobrdf/core/support/error.hpp"

namespace icobrdf {

namespace {

using h5::Shape;
using h5::ShapePattern;

// Largest level attribute accepted: level 15 already has 10 * 4^15 ~ 1e10 cells, beyond any int index.
constexpr int kMaxGridLevel = 15;

std::uint64_t u(Eigen::Index n) { return static_cast<std::uint64_t>(n); }

void write_rows3(h5::Group& g, const char* name, const RowMatrix3d& m, const char* unit, const char* what) {
  g.write(name, m.data(), Shape{u(m.rows()), 3}, unit, what);
}
void write_rows3(h5::Group& g, const char* name, const RowMatrix3i& m, const char* unit, const char* what) {
  static_assert(sizeof(int) == sizeof(std::int32_t), "int must be 32-bit");
  g.write(name, reinterpret_cast<const std::int32_t*>(m.data()), Shape{u(m.rows()), 3}, unit, what);
}
void write_ints(h5::Group& g, const char* name, const Eigen::VectorXi& v, const char* what) {
  if (v.size() == 0) return;
  g.write(name, reinterpret_cast<const std::int32_t*>(v.data()), Shape{u(v.size())}, "index", what);
}

void require_finite(const h5::Group& g, const char* name, const std::vector<double>& v) {
  for (size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]))
      g.fail(g.child_path(name), "expected finite values, found " + std::to_string(v[i]) + " at flat index " + std::to_string(i));
}

RowMatrix3d read_rows3d(const h5::Group& g, const char* name, std::int64_t rows, const h5::ReadLimits& lim) {
  auto a = g.read<double>(name, ShapePattern{rows, 3}, lim);
  require_finite(g, name, a.data);
  RowMatrix3d m(static_cast<Eigen::Index>(a.shape[0]), 3);
  std::copy(a.data.begin(), a.data.end(), m.data());
  return m;
}

RowMatrix3i read_rows3i(const h5::Group& g, const char* name, std::int64_t rows, std::int64_t lo, std::int64_t hi,
                        const h5::ReadLimits& lim) {
  auto a = g.read<std::int32_t>(name, ShapePattern{rows, 3}, lim);
  for (size_t i = 0; i < a.data.size(); ++i)
    if (a.data[i] < lo || a.data[i] >= hi)
      g.fail(g.child_path(name), "expected indices in [" + std::to_string(lo) + ", " + std::to_string(hi) + "), found " +
                                     std::to_string(a.data[i]) + " at flat index " + std::to_string(i));
  RowMatrix3i m(static_cast<Eigen::Index>(a.shape[0]), 3);
  std::copy(a.data.begin(), a.data.end(), m.data());
  return m;
}

Eigen::VectorXi read_map(const h5::Group& g, const char* name, int cells, const h5::ReadLimits& lim) {
  if (!g.has(name)) return {};
  auto a = g.read<std::int32_t>(name, ShapePattern{cells}, lim);
  for (size_t i = 0; i < a.data.size(); ++i)
    if (a.data[i] < 0 || a.data[i] >= cells)
      g.fail(g.child_path(name), "expected cell indices in [0, " + std::to_string(cells) + "), found " + std::to_string(a.data[i]));
  return Eigen::Map<const Eigen::VectorXi>(a.data.data(), cells);
}

}  // namespace

void write_grid(h5::Group& parent, const Grid& grid, const std::string& name) {
  try {
    validate(grid);
  } catch (const std::invalid_argument& e) {
    throw ArgumentError(std::string("cannot write grid: ") + e.what());
  }
  h5::Group g = parent.create_group(name);
  const std::uint64_t c = u(grid.cells());
  g.set_attr("kind", std::string(to_string(grid.kind)));
  g.set_attr("level", static_cast<std::int32_t>(grid.level));
  g.set_attr("cells", static_cast<std::int32_t>(grid.cells()));
  g.set_attr("cubature_degree", static_cast<std::int32_t>(grid.cubature_degree));
  write_rows3(g, "directions", grid.directions, "1", "representative unit direction of each cell, z >= 0");
  g.write("solid_angles", grid.solid_angles.data(), Shape{c}, "sr", "exact solid angle of each cell");
  g.write("cubature_offsets", grid.cubature_offsets.data(), Shape{c + 1}, "index",
          "cubature points of cell c are rows [offsets[c], offsets[c+1]) of cubature_points");
  write_rows3(g, "cubature_points", grid.cubature_points, "1", "cubature nodes, unit vectors");
  g.write("cubature_weights", grid.cubature_weights.data(), Shape{u(grid.cubature_weights.size())}, "sr",
          "cubature weights; those of one cell sum to its solid angle");
  if (grid.vertices.rows() > 0) write_rows3(g, "vertices", grid.vertices, "1", "mesh vertices, unit vectors");
  if (grid.faces.rows() > 0)
    write_rows3(g, "faces", grid.faces, "index", "vertex ids of each triangular cell, counter-clockwise seen from outside");
  if (grid.neighbours.rows() > 0)
    write_rows3(g, "neighbours", grid.neighbours, "index", "cell across the edge opposite faces[c, k]; -1 on the boundary");
  if (!grid.is_half.empty()) g.write("is_half", grid.is_half.data(), Shape{c}, "1", "1 for a cell cut in half by the equator");
  write_ints(g, "rotate_pi", grid.rotate_pi, "cell containing the image under rotation by pi about +z");
  write_ints(g, "mirror_xz", grid.mirror_xz, "cell containing the image under the mirror y -> -y");
  write_ints(g, "mirror_yz", grid.mirror_yz, "cell containing the image under the mirror x -> -x");
}

GridSummary read_grid_summary(const h5::Group& g) {
  GridSummary s;
  s.kind = g.attr_string("kind");
  s.level = static_cast<int>(g.attr_int("level", -1, kMaxGridLevel));
  s.cells = static_cast<int>(g.attr_int("cells", 1, std::numeric_limits<std::int32_t>::max()));
  return s;
}

Grid read_grid(const h5::Group& g, const h5::ReadLimits& lim) {
  g.check_links();
  const GridSummary s = read_grid_summary(g);
  Grid grid;
  try {
    grid.kind = parse_grid_kind(s.kind);
  } catch (const ArgumentError& e) {
    g.fail(g.path(), e.what());
  }
  grid.level = s.level;
  grid.cubature_degree = static_cast<int>(g.attr_int("cubature_degree", 0, 1000));
  const int c = s.cells;

  grid.directions = read_rows3d(g, "directions", c, lim);
  {
    auto a = g.read<double>("solid_angles", ShapePattern{c}, lim);
    require_finite(g, "solid_angles", a.data);
    grid.solid_angles = Eigen::Map<const Eigen::VectorXd>(a.data.data(), c);
  }
  {
    auto a = g.read<std::int64_t>("cubature_offsets", ShapePattern{std::int64_t{c} + 1}, lim);
    if (a.data[0] != 0) g.fail(g.child_path("cubature_offsets"), "expected first entry 0, found " + std::to_string(a.data[0]));
    for (int i = 0; i < c; ++i)
      if (a.data[i + 1] <= a.data[i])
        g.fail(g.child_path("cubature_offsets"), "expected strictly increasing offsets, found " + std::to_string(a.data[i]) +
                                                     " then " + std::to_string(a.data[i + 1]) + " at cell " + std::to_string(i));
    grid.cubature_offsets = std::move(a.data);
  }
  const std::int64_t q = grid.cubature_offsets.back();
  grid.cubature_points = read_rows3d(g, "cubature_points", q, lim);
  {
    auto a = g.read<double>("cubature_weights", ShapePattern{q}, lim);
    require_finite(g, "cubature_weights", a.data);
    grid.cubature_weights = Eigen::Map<const Eigen::VectorXd>(a.data.data(), static_cast<Eigen::Index>(q));
  }
  if (g.has("vertices")) grid.vertices = read_rows3d(g, "vertices", -1, lim);
  if (g.has("faces")) grid.faces = read_rows3i(g, "faces", c, 0, grid.vertices.rows(), lim);
  if (g.has("neighbours")) grid.neighbours = read_rows3i(g, "neighbours", c, -1, c, lim);
  if (g.has("is_half")) {
    auto a = g.read<std::uint8_t>("is_half", ShapePattern{c}, lim);
    for (auto v : a.data)
      if (v > 1) g.fail(g.child_path("is_half"), "expected 0 or 1, found " + std::to_string(v));
    grid.is_half = std::move(a.data);
  }
  grid.rotate_pi = read_map(g, "rotate_pi", c, lim);
  grid.mirror_xz = read_map(g, "mirror_xz", c, lim);
  grid.mirror_yz = read_map(g, "mirror_yz", c, lim);
  try {
    validate(grid);
  } catch (const std::invalid_argument& e) {
    g.fail(g.path(), e.what());
  }
  return grid;
}

}  // namespace icobrdf
