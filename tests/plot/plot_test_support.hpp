#pragma once
// What the picture tests share: a temporary folder removed with its files, and the distance of a drawn pixel
// from a colour.
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <string>

#include "icobrdf/plot/colormap.hpp"

namespace icobrdf::plot::test {

struct TempDir {
  std::string path;
  TempDir() {
    char t[] = "/tmp/icobrdf_plotXXXXXX";
    path = mkdtemp(t);
  }
  ~TempDir() { std::system(("rm -rf '" + path + "'").c_str()); }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string file(const std::string& n) const { return path + "/" + n; }
};

// Largest difference of the three sRGB bytes of a drawn pixel from those of colour c (components in [0, 1]).
inline int byte_distance(const std::array<int, 3>& a, const Rgb& c) {
  int d = 0;
  for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(a[k] - static_cast<int>(std::lround(c[k] * 255))));
  return d;
}

}  // namespace icobrdf::plot::test
