// libFuzzer target: the CSV sample reader (icobrdf/io/sample_csv.hpp read_sample_csv) and, on the same bytes, the
// direction-list readers (icobrdf/io/direction_csv.hpp), which share the CSV layer (icobrdf/io/csv.hpp).
// The options come from the input length (bit 0: radians, bit 1: strict), so seeds stay plain CSV text.
// On success: unit direction vectors in the upper hemisphere, finite values, weights >= 1 summing to the rows.
#include <cmath>

#include "fuzz/fuzz_support.hpp"
#include "icobrdf/io/direction_csv.hpp"
#include "icobrdf/io/sample_csv.hpp"

using namespace icobrdf;

namespace {

// A direction from angles in range is a unit vector up to rounding of sin / cos.
constexpr double kUnitTolerance = 1e-12;

void check_directions(const RowMatrix3d& d, const char* what) {
  for (Eigen::Index r = 0; r < d.rows(); ++r) {
    if (!d.row(r).allFinite() || std::abs(d.row(r).norm() - 1) > kUnitTolerance || d(r, 2) < -kUnitTolerance)
      fuzz::finding(std::string(what) + ": not a unit vector of the upper hemisphere");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  static const fuzz::InputFile file("csv", ".csv");
  file.write(data, size);
  SampleCsvOptions o;
  o.radians = (size & 1) != 0;
  o.strict = (size & 2) != 0;
  fuzz::expect_input_errors_only([&] {
    const BrdfSamples s = read_sample_csv(file.path(), o);
    check_directions(s.wi, "wi");
    check_directions(s.wr, "wr");
    if (s.values.rows() != s.wi.rows() || s.weights.size() != s.wi.rows() || s.lines.size() != static_cast<size_t>(s.wi.rows()))
      fuzz::finding("sample arrays disagree in length");
    if (!s.values.allFinite()) fuzz::finding("read_sample_csv returned a non-finite value");
    if (s.weights.sum() != static_cast<double>(s.rows) || (s.weights.array() < 1).any())
      fuzz::finding("sample weights do not count the rows");
    if (s.rows - s.duplicates_merged != s.wi.rows()) fuzz::finding("duplicate count disagrees with the samples");
  });
  fuzz::expect_input_errors_only([&] {
    const DirectionPairs p = read_direction_pairs_csv(file.path(), o.radians);
    check_directions(p.wi, "pair wi");
    check_directions(p.wr, "pair wr");
  });
  fuzz::expect_input_errors_only([&] { check_directions(read_directions_csv(file.path(), o.radians), "direction"); });
  return 0;
}
