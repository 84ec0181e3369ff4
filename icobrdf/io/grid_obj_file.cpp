#include "icobrdf/io/grid_obj_file.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/atomic_write.hpp"
#include "icobrdf/mesh/grid_obj.hpp"

namespace icobrdf {

void write_grid_obj_file(const Grid& g, const std::string& path) {
  if (!has_triangle_mesh(g))
    throw IoError("cannot export '" + path + "': the grid has no triangle mesh (kind " + std::string(to_string(g.kind)) + ")");
  atomic_write(path, [&](const std::string& temp) {
    std::FILE* f = std::fopen(temp.c_str(), "w");
    if (f == nullptr) throw IoError(path + ": cannot write: " + std::strerror(errno));
    const bool ok = write_grid_obj(g, f);
    const int err = ok ? 0 : errno;
    if (std::fclose(f) != 0 || !ok) throw IoError(path + ": cannot write: " + std::strerror(err ? err : errno));
  });
}

}  // namespace icobrdf
