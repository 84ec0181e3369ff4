// Fit a model, smooth it, evaluate it, and write its spectrum.
//   fit_smooth_eval OUT.h5
// Fits GGX (alpha 0.3) at level 4, order 8, applies a Hann low-pass filter to the coefficients, evaluates
// both at a few direction pairs next to the model, and writes the filtered spectrum to OUT.h5.
#include <cstdio>
#include <memory>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/basis/lowpass_filter.hpp"
#include "icobrdf/core/projection/projection.hpp"
#include "icobrdf/core/spectrum/spectrum_ops.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/spectrum_file.hpp"
#include "icobrdf/pipeline/fit_source.hpp"

int main(int argc, char** argv) {
  using namespace icobrdf;
  if (argc != 2) return std::fprintf(stderr, "usage: fit_smooth_eval OUT.h5\n"), 2;
  const std::unique_ptr<BrdfSource> model = open_source("model:ggx:alpha=0.3");
  FitRequest request;  // level 4, order 8, equal-area grid, cell-averaged sampling
  const Spectrum fitted = fit_source(*model, request).spectrum;
  Spectrum smoothed = fitted;  // a value type: copies own their matrices
  const LowPassFilter hann = parse_lowpass_filter("hann");
  for (auto& c : smoothed.channels) c = filter_coefficients(c, smoothed.order, hann);
  smoothed.filter = hann.name();

  RowMatrix3d wi(3, 3), wr(3, 3);  // unit vectors, +z the normal; w_i toward the light
  for (int k = 0; k < 3; ++k) {
    wi.row(k) = direction_from_angles(0.3 * k, 0.0).transpose();
    wr.row(k) = direction_from_angles(0.3 * k, M_PI).transpose();  // the mirror direction
  }
  const Eigen::MatrixXd exact = model->eval(wi, wr);
  const Eigen::VectorXd f = evaluate_coefficients(fitted.channels[0], fitted.order, wi, wr);
  const Eigen::VectorXd s = evaluate_coefficients(smoothed.channels[0], smoothed.order, wi, wr);
  for (int k = 0; k < 3; ++k) std::printf("theta %.1f: model %.5f  fit %.5f  smoothed %.5f 1/sr\n", 0.3 * k, exact(k, 0), f[k], s[k]);
  write_spectrum_file(argv[1], smoothed, nullptr, "ggx_smoothed");
  std::printf("wrote %s\n", argv[1]);
  return 0;
}
