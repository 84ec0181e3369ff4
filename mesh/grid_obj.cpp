#include "mesh/grid_obj.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

#include "core/error.hpp"

namespace icobrdf {

void write_grid_obj(const Grid& g, const std::string& path) {
  if (g.vertices.rows() == 0 || g.faces.rows() == 0)
    throw IoError("cannot export '" + path + "': the grid has no triangle mesh (kind " + std::string(to_string(g.kind)) + ")");
  std::string tmpl = path + ".tmp.XXXXXX";
  const int fd = mkstemp(tmpl.data());
  if (fd < 0) throw IoError("cannot create a temporary file next to '" + path + "': " + std::strerror(errno));
  FILE* f = fdopen(fd, "w");
  if (f == nullptr) {
    const int err = errno;
    close(fd);
    std::remove(tmpl.c_str());
    throw IoError("cannot write '" + tmpl + "': " + std::strerror(err));
  }
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
  const int werr = ok ? 0 : errno;
  ok = ok && std::fflush(f) == 0 && fsync(fileno(f)) == 0;
  const int ferr = ok ? 0 : (werr ? werr : errno);
  if (std::fclose(f) != 0 && ok) {
    ok = false;
  }
  if (!ok || std::rename(tmpl.c_str(), path.c_str()) != 0) {
    const int err = ferr ? ferr : errno;
    std::remove(tmpl.c_str());
    throw IoError("cannot write '" + path + "': " + std::strerror(err));
  }
}

}  // namespace icobrdf
