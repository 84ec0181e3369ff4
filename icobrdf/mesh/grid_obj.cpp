#include "icobrdf/mesh/grid_obj.hpp"

namespace icobrdf {

bool has_triangle_mesh(const Grid& g) { return g.vertices.rows() > 0 && g.faces.rows() > 0; }

bool write_grid_obj(const Grid& g, std::FILE* f) {
  bool ok = std::fprintf(f, "# icobrdf %s hemisphere grid, level %d: %d cells, %d vertices\n", to_string(g.kind), g.level,
                         g.cells(), static_cast<int>(g.vertices.rows())) > 0;
  for (Eigen::Index v = 0; ok && v < g.vertices.rows(); ++v)
    ok = std::fprintf(f, "v %.17g %.17g %.17g\n", g.vertices(v, 0), g.vertices(v, 1), g.vertices(v, 2)) > 0;
  for (Eigen::Index v = 0; ok && v < g.vertices.rows(); ++v)
    ok = std::fprintf(f, "vn %.17g %.17g %.17g\n", g.vertices(v, 0), g.vertices(v, 1), g.vertices(v, 2)) > 0;
  for (Eigen::Index c = 0; ok && c < g.faces.rows(); ++c) {
    const int a = g.faces(c, 0) + 1, b = g.faces(c, 1) + 1, d = g.faces(c, 2) + 1;
    ok = std::fprintf(f, "f %d//%d %d//%d %d//%d\n", a, a, b, b, d, d) > 0;
  }
  return ok && std::fflush(f) == 0;
}

}  // namespace icobrdf
