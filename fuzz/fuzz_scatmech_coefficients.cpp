// libFuzzer target: the SCATMECH coefficient-file reader (icobrdf/io/scatmech_coefficients.hpp) and, for files it
// accepts, the import as a Spectrum (at a wavelength of 0.6328 um, so p != 0 rows are accepted).
// On success: rows counted consistently, order within kMaxScatmechOrder, finite spectrum coefficients.
#include "icobrdf/core/support/error.hpp"
#include "fuzz/fuzz_support.hpp"
#include "icobrdf/io/scatmech_coefficients.hpp"

using namespace icobrdf;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  static const fuzz::InputFile file("scatmech", ".txt");
  file.write(data, size);
  fuzz::expect_input_errors_only([&] {
    const ScatmechCoefficients c = read_scatmech_coefficients(file.path());
    if (c.unpolarized_rows + c.polarized_rows != static_cast<long long>(c.rows.size()) || c.unpolarized_rows < 1)
      fuzz::finding("row counts disagree");
    if (c.order < 0 || c.order > kMaxScatmechOrder) fuzz::finding("order out of range: " + std::to_string(c.order));
    ScatmechImportOptions o;
    o.wavelength_um = 0.6328;
    Spectrum s;
    try {
      s = scatmech_to_spectrum(c, o);
    } catch (const ArgumentError& e) {
      fuzz::finding(std::string("import of an accepted file refused: ") + e.what());
    }
    for (const auto& ch : s.channels)
      if (!ch.allFinite()) fuzz::finding("import gave non-finite coefficients");
  });
  return 0;
}
