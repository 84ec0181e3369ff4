#pragma once
// A grid's Wavefront OBJ file (text: icobrdf/mesh/grid_obj.hpp), written atomically (icobrdf/io/atomic_write.hpp): the
// target is either the complete new file or untouched. Throws IoError (one line: path and reason) if the
// grid has no triangle mesh or the file system refuses; no file is left behind then.
#include <string>

#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf {

void write_grid_obj_file(const Grid& grid, const std::string& path);

}  // namespace icobrdf
