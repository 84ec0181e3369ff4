#pragma once
// Wavefront OBJ export of a tessellation Grid (vertices and triangular cells) for viewing in any mesh
// viewer. Vertex normals equal the (unit) vertex positions. Faces are counter-clockwise seen from outside.
#include <string>

#include "core/grid.hpp"

namespace icobrdf {

// Writes to a temporary file in the target's directory and renames it onto `path`, so the target is
// either complete or untouched. Throws IoError (one line: path and reason) if the grid has no triangle
// mesh or the file system refuses; no file is left behind then.
void write_grid_obj(const Grid& grid, const std::string& path);

}  // namespace icobrdf
