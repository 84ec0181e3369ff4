// libFuzzer target: the model spec parser (icobrdf/core/models/model_registry.hpp parse_model), on the input bytes as the spec
// text a user gives after "model:". The parser returns a model or throws ArgumentError with a one-line
// message. A returned model must behave at a fixed set of direction pairs (normal incidence, grazing both
// ways, the horizon itself, a mirror pair and scattered pairs): every channel's value finite and >= 0, and
// equal under exchange of the two directions when the model reports itself reciprocal.
#include <cmath>
#include <string>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "fuzz/fuzz_support.hpp"

using namespace icobrdf;

namespace {

// Reciprocity of the built-in models holds to ~1e-14 relative (tests/core); the fuzzed parameters reach
// the ends of their ranges, where a few more ulps are lost in powers and exponentials.
constexpr double kReciprocityTolerance = 1e-9;
// Spec lengths beyond this only repeat terms; longer inputs are skipped to keep each run fast.
constexpr size_t kMaxSpecLength = 512;

RowMatrix3d probe_directions() {
  const double deg = M_PI / 180;
  const double angles[][2] = {{0, 0},  {89.999, 0}, {90, 0},  {90, 180}, {45, 0},  {45, 180},
                              {30, 70}, {60, 250},  {10, 300}, {80, 120}, {1e-6, 5}, {75, 75}};
  const int n = static_cast<int>(sizeof angles / sizeof angles[0]);
  RowMatrix3d d(n, 3);
  for (int k = 0; k < n; ++k) d.row(k) = direction_from_angles(angles[k][0] * deg, angles[k][1] * deg).transpose();
  return d;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  if (size > kMaxSpecLength) return 0;
  static const RowMatrix3d probes = probe_directions();
  const std::string spec(reinterpret_cast<const char*>(data), size);
  fuzz::expect_user_errors_only([&] {
    const auto model = parse_model(spec);
    if (model->channels() < 1) fuzz::finding("model '" + spec + "' has no channel");
    const Eigen::Index n = probes.rows();
    // Every ordered pair of probes, and the same pairs exchanged.
    RowMatrix3d wi(n * n, 3), wr(n * n, 3);
    for (Eigen::Index a = 0; a < n; ++a)
      for (Eigen::Index b = 0; b < n; ++b) {
        wi.row(a * n + b) = probes.row(a);
        wr.row(a * n + b) = probes.row(b);
      }
    Eigen::MatrixXd f(n * n, model->channels()), swapped(n * n, model->channels());
    model->eval(wi, wr, f);
    model->eval(wr, wi, swapped);
    for (Eigen::Index k = 0; k < f.rows(); ++k)
      for (Eigen::Index c = 0; c < f.cols(); ++c) {
        const double v = f(k, c), w = swapped(k, c);
        if (!std::isfinite(v) || v < 0)
          fuzz::finding("model '" + model->spec() + "' gives f = " + std::to_string(v) + " at pair " + std::to_string(k));
        if (model->is_reciprocal() && std::abs(v - w) > kReciprocityTolerance * std::max(std::abs(v), std::abs(w)))
          fuzz::finding("model '" + model->spec() + "' reports reciprocity but f(wi, wr) = " + std::to_string(v) +
                        " != f(wr, wi) = " + std::to_string(w) + " at pair " + std::to_string(k));
      }
  });
  return 0;
}
