#pragma once
// A tessellation's figures as `icobrdf grid` reports them: kind, level, cells (whole and half), the cells'
// solid angles in sr (min, max and sum, which is 2 pi up to rounding; the max/min ratio over the whole cells),
// the cubature's degree and points, and the mesh's vertices.
#include <nlohmann/json.hpp>

#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf {

// kind, level, cells, whole_cells, half_cells, solid_angle_min, solid_angle_max, solid_angle_sum (summed in
// long double), whole_cell_ratio, cubature_degree, cubature_points, vertices.
nlohmann::json grid_summary_json(const Grid& g);

}  // namespace icobrdf
