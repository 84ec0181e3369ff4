// libFuzzer target: the RGL material reader (icobrdf/io/rgl_bsdf.hpp, over icobrdf/io/tensor_file.hpp). The input is the
// file. For files it accepts, a fixed set of direction pairs (normal, oblique, grazing, below the horizon,
// every azimuth quadrant for the symmetry reductions) is evaluated on every channel: the values must be
// finite (every table was checked finite, sigma > 0 when it divides, and the cosine is floored).
// Seeds: fuzz/corpus/rgl_bsdf/ (small valid RGB, spectral and anisotropic files).
#include <cmath>

#include "icobrdf/core/support/error.hpp"
#include "fuzz/fuzz_support.hpp"
#include "icobrdf/io/rgl_bsdf.hpp"

using namespace icobrdf;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  static const fuzz::InputFile file("rgl", ".bsdf");
  file.write(data, size);
  fuzz::expect_input_errors_only([&] {
    auto b = std::make_shared<const RglBsdf>(read_rgl_bsdf(file.path()));
    std::vector<double> lambdas = b->spectral ? b->wavelengths : std::vector<double>{0, 1, 2};
    const RglModel model(b, lambdas, "fuzz");
    const double dirs[][3] = {{0, 0, 1}, {0.6, 0.0, 0.8}, {-0.6, 0.0, 0.8}, {0.0, 0.6, 0.8}, {0.0, -0.6, 0.8},
                              {0.48, -0.36, 0.8}, {-0.48, 0.36, 0.8}, {1, 0, 0}, {0.999, 0, 0.0447}, {0.6, 0, -0.8}};
    const int n = sizeof dirs / sizeof dirs[0];
    RowMatrix3d wi(n * n, 3), wr(n * n, 3);
    for (int a = 0; a < n; ++a)
      for (int c = 0; c < n; ++c) {
        wi.row(a * n + c) << dirs[a][0], dirs[a][1], dirs[a][2];
        wr.row(a * n + c) << dirs[c][0], dirs[c][1], dirs[c][2];
      }
    Eigen::MatrixXd out(n * n, model.channels());
    model.eval(wi, wr, out);
    if (!out.allFinite()) fuzz::finding("an accepted RGL file evaluates to a non-finite value");
  });
  return 0;
}
