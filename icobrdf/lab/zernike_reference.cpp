#include "icobrdf/lab/zernike_reference.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "icobrdf/core/basis/zernike.hpp"
#include "icobrdf/lab/report_format.hpp"

namespace icobrdf::lab {
namespace {

constexpr double kRefEps = std::numeric_limits<double>::epsilon();  // 2^-52

#if defined(__SIZEOF_FLOAT128__)
using Quad = __float128;
constexpr const char* kQuadName = "binary128 (__float128)";
constexpr double kQuadRoundoff = 0x1p-113;
#else
using Quad = long double;
constexpr const char* kQuadName = "long double";
constexpr double kQuadRoundoff = std::numeric_limits<long double>::epsilon() / 2;
#endif

}  // namespace

std::vector<ZernikeRow> zernike_vs_closed_sum(int n_max, int n_block, int samples) {
  std::vector<Quad> fact(static_cast<size_t>(n_max) + 1);
  fact[0] = 1;
  for (int k = 1; k <= n_max; ++k) fact[static_cast<size_t>(k)] = fact[static_cast<size_t>(k) - 1] * k;
  std::vector<double> rec(static_cast<size_t>(zernike_radial_count(n_max)));
  std::vector<ZernikeRow> rows;
  for (int n0 = 0; n0 <= n_max; n0 += n_block) rows.push_back({n0, std::min(n_max, n0 + n_block - 1)});
  for (int s = 0; s < samples; ++s) {
    const double rho = static_cast<double>(s) / (samples - 1);  // includes 0 and 1
    zernike_radial_all(n_max, rho, rec.data());
    for (int n = 0; n <= n_max; ++n)
      for (int l = n % 2; l <= n; l += 2) {
        Quad sum = 0, abs_sum = 0;
        double sum_d = 0.0;
        for (int k = 0; k <= (n - l) / 2; ++k) {
          const Quad c = fact[static_cast<size_t>(n - k)] /
                         (fact[static_cast<size_t>(k)] * fact[static_cast<size_t>((n + l) / 2 - k)] * fact[static_cast<size_t>((n - l) / 2 - k)]);
          Quad p = 1;
          for (int e = 0; e < n - 2 * k; ++e) p *= rho;
          const Quad term = (k % 2 ? -c : c) * p;
          sum += term;
          abs_sum += term < 0 ? -term : term;
          sum_d += static_cast<double>(k % 2 ? -c : c) * std::pow(rho, n - 2 * k);
        }
        auto& row = rows[static_cast<size_t>(n / n_block)];
        const double ref = static_cast<double>(sum);
        row.recurrence_error = std::max(row.recurrence_error, std::abs(rec[static_cast<size_t>(zernike_radial_index(n, l))] - ref));
        row.reference_error_bound = std::max(row.reference_error_bound, (n + 4) * kQuadRoundoff * static_cast<double>(abs_sum));
        row.closed_double_error = std::max(row.closed_double_error, std::abs(sum_d - ref));
        row.closed_double_estimate = std::max(row.closed_double_estimate, kRefEps * static_cast<double>(abs_sum));
      }
  }
  return rows;
}

void add_zernike_reference(const SectionOptions& o, ReportSection& s, std::string& md) {
  // Degrees to 40: beyond, the binary128 closed sum's own rounding bound (~3x per degree) exceeds 1e-3 of
  // the recurrence's documented error and the reference stops being one.
  const int n_max = 40, block = 10, samples = o.quick ? 51 : 201;
  const auto zr = zernike_vs_closed_sum(n_max, block, samples);
  std::vector<std::vector<std::string>> rows;
  nlohmann::json jz = nlohmann::json::array();
  for (const auto& r : zr) {
    rows.push_back({fmt::format("{}-{}", r.n_from, r.n_to), sci(r.recurrence_error), sci(kZernikeAbsError, 0), sci(r.reference_error_bound),
                    sci(r.closed_double_error), sci(r.closed_double_estimate)});
    jz.push_back({{"n_from", r.n_from},
                  {"n_to", r.n_to},
                  {"recurrence_error", r.recurrence_error},
                  {"documented_error", kZernikeAbsError},
                  {"reference_error_bound", r.reference_error_bound},
                  {"closed_sum_double_error", r.closed_double_error},
                  {"closed_sum_double_estimate", r.closed_double_estimate}});
  }
  s.data["zernike"] = {{"n_max", n_max}, {"samples", samples}, {"reference", kQuadName}, {"rows", jz}};
  md += fmt::format(
      "Zernike radial polynomials R_n^l, all l, at {} values of rho in [0, 1] (0 and 1 included): the library's "
      "recurrence against the closed factorial sum (eq. 3) evaluated in {} (its own rounding bound "
      "(n + 4) u_q sum|c_k rho^(n-2k)| in the fourth column), and the same closed sum in double, whose "
      "cancellation error is ~ eps sum|c_k rho^(n-2k)| (last column):\n\n",
      samples, kQuadName);
  md += md_table({"n", "recurrence max error", "documented", "reference bound", "closed sum in double: error", "expected ~"}, rows);
}

}  // namespace icobrdf::lab
