#pragma once
// `icobrdf bench measured`: real measured materials (RGL .bsdf files) through the bank builder, beside the
// Neural-BRDF networks the authors released for the same materials (icobrdf/lab/nbrdf_network.hpp).
//
// Per material:
//   * the bank builder's representation (a scene of all the materials, `metric = "cosine"`, level 4,
//     order_max 4 (the hybrids' bodies), no LUTs stored, the target and representations given, fitted as
//     `icobrdf bank build` fits them): representation, bytes, seconds of the whole build (materials fitted
//     at once as the builder plans them);
//   * small lobes: isotropic half-angle lobes (mean-cosine quantity, icobrdf/core/fit/half_angle_fit.hpp)
//     within byte budgets (kMeasuredBudgets; 2,700 B, NBRDF's size, is one of them), each budget's storage
//     (factors per channel or shared with channel scales; float64, float32, int16 or int8), grid and rank
//     chosen on a validation set of pairs (its own seed), reported on the test pairs, the bytes those the
//     lobe stores (HalfAngleFactors::bytes + the bank's header) and the errors those of the stored values;
//   * NBRDF at kNbrdfBytes, when the network folder holds <file stem>.h5.
// Errors (cosine metric: w = cos(theta_i) cos(theta_r), relative L2 over pairs and channels
// |w (f_fit - f)| / |w f|) on `pairs` test pairs uniform in solid angle, seeded by the material's name, which
// no fit sees: against the data f and against its reciprocal part (f(a, b) + f(b, a)) / 2; the data's
// asymmetry |w (f - f_rec)| / |w f| bounds from below what any reciprocal representation (every lobe; the
// modes) reaches against f.
#include <functional>
#include <string>
#include <vector>

namespace icobrdf::lab {

// Byte budgets of the small lobes (the curve of error against bytes).
inline constexpr long long kMeasuredBudgets[] = {1350, 2700, 5400, 10800, 21600, 43200, 65536};

struct MeasuredBenchOptions {
  std::vector<std::string> files;  // RGL .bsdf files
  std::string nbrdf_dir;           // folder of <stem>.h5 networks; empty: no NBRDF column
  std::string work_dir;            // the scene and bank are written here
  double target = 0.02;
  std::vector<std::string> representations{"half-angle", "hybrid"};
  int pairs = 20000;
  int materials_at_once = 0;  // as `bank build --materials-at-once`
  bool small_lobes = true;
  bool bank = true;  // false: no bank build (the rows' bank columns stay empty)
  std::vector<long long> budgets{std::begin(kMeasuredBudgets), std::end(kMeasuredBudgets)};  // of the small lobes
  std::function<void(const std::string&)> progress;  // may be empty
};

struct BudgetPoint {
  long long budget = 0, bytes = 0;
  std::string grid;  // "n_t x n_theta_d x n_phi_d rank R"
  double error = 0, error_reciprocal = 0;
};

struct MeasuredRow {
  std::string name, file;
  std::string representation;  // the builder's choice
  bool met = false;            // it met the target (on the builder's own held-out pairs)
  long long bytes = 0;
  double error = 0, error_reciprocal = 0, asymmetry = 0;
  double noise = 0;            // the data's noise figure on the test pairs (icobrdf/pipeline/held_out.hpp noise_figure)
  bool has_nbrdf = false;
  double nbrdf_error = 0, nbrdf_error_reciprocal = 0;
  std::vector<BudgetPoint> budgets;  // ascending budgets
  double small_seconds = 0;
};

struct MeasuredBench {
  std::vector<MeasuredRow> rows;
  double bank_seconds = 0;
  int threads = 0;
  double target = 0;
  std::vector<long long> budgets;
};

// InputError for unreadable files, ArgumentError for bad options (no files, pairs < 100, target <= 0, a budget <= 0).
MeasuredBench run_measured_bench(const MeasuredBenchOptions& options);
// The report as Markdown (tables of the rows, the budgets and the machine's thread count).
std::string measured_bench_markdown(const MeasuredBench& bench);
// Error against the reciprocal part versus bytes: one series per material (small lobes), NBRDF and the
// builder's choices as points; PNG at `png_path`.
void plot_measured_bench(const MeasuredBench& bench, const std::string& png_path);
// The .bsdf files named: files as given, folders by their *.bsdf files in name order. InputError for a missing
// path or a folder without .bsdf files.
std::vector<std::string> bsdf_files(const std::vector<std::string>& inputs);
// Writes DIR/report.md (the markdown and the figure's link) and DIR/error-vs-bytes.png; returns the markdown.
// IoError when report.md cannot be written.
std::string write_measured_report(const MeasuredBench& bench, const std::string& dir);

}  // namespace icobrdf::lab
