#pragma once
// Wavefront OBJ text of a tessellation Grid (vertices and triangular cells) for viewing in any mesh viewer.
// Vertex normals equal the (unit) vertex positions. Faces are counter-clockwise seen from outside.
// The file itself is written atomically by icobrdf/io/grid_obj_file.hpp.
#include <cstdio>

#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf {

// Whether the grid has a triangle mesh to export (vertices and faces).
bool has_triangle_mesh(const Grid& grid);

// Writes the OBJ text of a grid with a triangle mesh to `out`; false when a write failed (errno tells why).
bool write_grid_obj(const Grid& grid, std::FILE* out);

}  // namespace icobrdf
