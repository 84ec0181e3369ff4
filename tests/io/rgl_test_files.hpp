#pragma once
// Small RGL material files (icobrdf/io/rgl_bsdf.hpp) for tests: every table is given as a function of its node
// indices, so a test knows each stored value by construction.
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "icobrdf/io/tensor_file.hpp"

namespace icobrdf::test {

struct RglFileSpec {
  std::vector<double> theta{0.0}, phi{0.0};  // node values (use float32-exact values)
  std::vector<double> wavelengths;           // empty: an "rgb" file
  int w = 5, h = 5;                          // nodes of the vndf and value tables (x = u_theta along w)
  bool jacobian = false;
  double ndf = 1.0, sigma = 1.0;             // constant 2 x 2 tables
  std::function<double(int p, int t, int k, int j)> vndf = [](int, int, int, int) { return 1.0; };
  std::function<double(int p, int t, int c, int k, int j)> value = [](int, int, int, int, int) { return 1.0; };
};

inline std::vector<TensorField> rgl_fields(const RglFileSpec& s) {
  const auto np = static_cast<std::uint64_t>(s.phi.size()), nt = static_cast<std::uint64_t>(s.theta.size());
  const std::uint64_t nc = s.wavelengths.empty() ? 3 : s.wavelengths.size();
  const auto w = static_cast<std::uint64_t>(s.w), h = static_cast<std::uint64_t>(s.h);
  std::vector<double> vndf, lum, val;
  for (int p = 0; p < static_cast<int>(np); ++p)
    for (int t = 0; t < static_cast<int>(nt); ++t) {
      for (int j = 0; j < s.h; ++j)
        for (int k = 0; k < s.w; ++k) vndf.push_back(s.vndf(p, t, k, j)), lum.push_back(1.0);
      for (int c = 0; c < static_cast<int>(nc); ++c)
        for (int j = 0; j < s.h; ++j)
          for (int k = 0; k < s.w; ++k) val.push_back(s.value(p, t, c, k, j));
    }
  std::vector<TensorField> f;
  f.push_back(text_field("description", "test material"));
  f.push_back(float32_field("phi_i", {np}, s.phi));
  f.push_back(float32_field("theta_i", {nt}, s.theta));
  f.push_back(float32_field("sigma", {2, 2}, std::vector<double>(4, s.sigma)));
  f.push_back(float32_field("ndf", {2, 2}, std::vector<double>(4, s.ndf)));
  f.push_back(float32_field("vndf", {np, nt, h, w}, vndf));
  f.push_back(float32_field("luminance", {np, nt, h, w}, lum));
  if (s.wavelengths.empty()) {
    f.push_back(float32_field("rgb", {np, nt, 3, h, w}, val));
  } else {
    f.push_back(float32_field("wavelengths", {nc}, s.wavelengths));
    f.push_back(float32_field("spectra", {np, nt, nc, h, w}, val));
  }
  f.push_back(uint8_field("jacobian", {1}, {static_cast<std::uint8_t>(s.jacobian ? 1 : 0)}));
  return f;
}

}  // namespace icobrdf::test
