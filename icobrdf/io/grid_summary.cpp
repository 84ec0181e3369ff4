#include "icobrdf/io/grid_summary.hpp"

#include <algorithm>

namespace icobrdf {

nlohmann::json grid_summary_json(const Grid& g) {
  int half = 0;
  double wmin = 0, wmax = 0;
  long double sum = 0;
  bool first = true;
  for (int c = 0; c < g.cells(); ++c) {
    sum += g.solid_angles[c];
    half += g.is_half[c];
    if (g.is_half[c]) continue;
    wmin = first ? g.solid_angles[c] : std::min(wmin, g.solid_angles[c]);
    wmax = first ? g.solid_angles[c] : std::max(wmax, g.solid_angles[c]);
    first = false;
  }
  nlohmann::json j;
  j["kind"] = to_string(g.kind);
  j["level"] = g.level;
  j["cells"] = g.cells();
  j["whole_cells"] = g.cells() - half;
  j["half_cells"] = half;
  j["solid_angle_min"] = g.solid_angles.minCoeff();
  j["solid_angle_max"] = g.solid_angles.maxCoeff();
  j["solid_angle_sum"] = static_cast<double>(sum);
  j["whole_cell_ratio"] = wmax / wmin;
  j["cubature_degree"] = g.cubature_degree;
  j["cubature_points"] = g.cubature_points.rows();
  j["vertices"] = g.vertices.rows();
  return j;
}

}  // namespace icobrdf
