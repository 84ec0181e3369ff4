// libFuzzer target: the MERL reader (icobrdf/io/merl.hpp read_merl).
//
// A MERL file must be exactly 34,992,012 bytes, far beyond useful fuzz inputs, so the first input byte picks
// how the file is made from the rest:
//   even: the file is the remaining bytes as they are (headers, dims, short and truncated files);
//   odd:  bytes 1..12 are the header, the bytes after them are repeated to fill the 3 x 90 x 90 x 180
//         doubles (zeros when there are none), and (first byte >> 1) trailing bytes are appended; this reaches
//         the sample checks (NaN / Inf, -1 sentinels, all samples missing) and the trailing-bytes check.
// On success every value is checked: finite and >= 0, or NaN exactly where the table counts a missing sample.
// (merl_samples is not run: it only walks the validated table, and at full size it would take seconds per
// input under the sanitizers.)
#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "fuzz/fuzz_support.hpp"
#include "icobrdf/io/merl.hpp"

using namespace icobrdf;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  static const fuzz::InputFile file("merl", ".binary");
  if (size == 0) return 0;
  const std::uint8_t mode = data[0];
  ++data;
  --size;
  if ((mode & 1) == 0) {
    file.write(data, size);
  } else {
    static std::vector<unsigned char> bytes;
    const size_t trailing = mode >> 1;
    bytes.assign(static_cast<size_t>(kMerlFileBytes) + trailing, 0);
    std::memcpy(bytes.data(), data, std::min<size_t>(size, 12));
    if (size > 12) {
      const std::uint8_t* body = data + 12;
      const size_t n = size - 12;
      for (size_t at = 12; at < static_cast<size_t>(kMerlFileBytes); at += n)
        std::memcpy(bytes.data() + at, body, std::min(n, static_cast<size_t>(kMerlFileBytes) - at));
    }
    file.write(bytes.data(), bytes.size());
  }
  fuzz::expect_input_errors_only([&] {
    const MerlTable t = read_merl(file.path());
    std::int64_t missing = 0;
    for (double v : t.f) {
      if (std::isnan(v)) ++missing;
      else if (!(std::isfinite(v) && v >= 0)) fuzz::finding("read_merl returned a value " + std::to_string(v));
    }
    if (missing != t.missing_total()) fuzz::finding("missing-sample count disagrees with the NaN entries");
  });
  return 0;
}
