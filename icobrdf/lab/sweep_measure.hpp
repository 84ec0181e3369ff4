#pragma once
// The measurements of `icobrdf bench sweep`: for every (level, order) of the equal-area tessellation, the
// grid's resolving power (Gram error, condition number), the cost of its operators, and for every model
// the cost of one projection and the error of the reconstructed BRDF against the exact model at held-out
// direction pairs. icobrdf/lab/sweep_report.hpp turns a SweepResult into RESULTS.h5, report.md and PNG figures.
//
// Per (level, order) row:
//   cells, modes                 C = 10 4^L + 2^(L+1) cells, M = (N+1)(N+2)/2 modes
//   gram_error, condition        max |G - I| and lambda_max / lambda_min of G = B^T W B (icobrdf/core/projection/discrete_basis.hpp)
//   supported                    gram_error <= gram_tolerance and G non-singular; unsupported rows are not
//                                fitted (their model columns are NaN)
//   grid_seconds                 build_fitting_grid of the level (the same for every order of the level)
//   basis_seconds                build_discrete_basis: B, W, G, Gram error and condition number
//   operator_seconds             make_projection: P = W B G^-1
//   reconstruct_seconds          B C B^T, the cells x cells LUT of one spectrum (NaN when that LUT would
//                                exceed kMaxReconstructLutBytes, i.e. is not materialized)
//   pairs_seconds                evaluation of one spectrum at the held-out pairs (icobrdf/core/spectrum/spectrum_ops.hpp)
//   basis_bytes, projection_bytes, lut_bytes   B and G, P, and the reconstructed LUT (0 when not materialized)
//   peak_rss_bytes               the process's peak resident set so far (getrusage; monotone over the run)
// Per (level, order, model): project_seconds (fit_model: streaming projection without a LUT, Helmholtz
// symmetrization, figures), error_l2 = ||f_fit - f||_2 / ||f||_2 and error_max = max|f_fit - f| / max|f|
// over the held-out pairs, and error_l2_cosine, the same L2 ratio of cos(theta_i) cos(theta_r) f (the
// projected-solid-angle weighting a renderer integrates with, which keeps the grazing growth of microfacet
// models from dominating).
//
// Held-out pairs: both directions uniform in solid angle (cos theta uniform in [0, 1], phi uniform),
// drawn by std::mt19937_64 with a fixed seed: the same pairs for every level, order and model. They come
// from a continuous distribution, so with probability 1 no pair sits at a cell centre (where centre
// sampling would be exact by construction).
// Timings are wall-clock seconds; a step shorter than kRepeatBelowSeconds is repeated up to kTimingRepeats
// times and the best time kept.
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "icobrdf/core/projection/lut.hpp"
#include "icobrdf/lab/machine.hpp"
#include "icobrdf/lab/report_section.hpp"

namespace icobrdf::lab::sweep {

// Largest level and order the sweep accepts (level 6 = 41088 cells, order 32 = 561 modes).
inline constexpr int kMaxSweepLevel = 6;
inline constexpr int kMaxSweepOrder = 32;
// The order up to which each level's supported order is searched (the leading blocks of one Gram matrix).
inline constexpr int kSupportSearchOrder = kMaxSweepOrder;
// Reconstructed LUTs B C B^T are materialized (and timed) up to this size: level 4 (2562^2 x 8 B = 53 MB)
// is; level 5 (10304^2 x 8 B = 849 MB) is not, on a shared 2-core machine.
inline constexpr std::int64_t kMaxReconstructLutBytes = std::int64_t{256} << 20;
// Timing: steps faster than this are repeated (best of kTimingRepeats) to see past timer and cache noise.
inline constexpr double kRepeatBelowSeconds = 0.05;
inline constexpr int kTimingRepeats = 5;
// Held-out pairs: default count, quick-run count, and the generator's seed. The errors of lobes that grow
// towards grazing angles are heavy-tailed over the pairs: at level 5, order 20 two sets of 2000 pairs gave
// 3.3e-2 and 8.5e-2 for Oren-Nayar and 0.34 and 0.56 for GGX alpha 0.5, against 7.4e-2 and 0.37 with 100000;
// 20000 pairs come within about 10% of those for 15% more run time.
inline constexpr int kDefaultHeldOutPairs = 20000;
inline constexpr int kQuickHeldOutPairs = 200;
inline constexpr std::uint64_t kHeldOutSeed = 20260522;

// Default model suite: from Lambert to near-mirror. Minnaert's k = 1.5 is not an integer, so
// (cos ti cos tr)^0.5 has no finite spectrum; Lafortune with cx = cy = cz = 1 is a lobe about the incident
// direction itself (retroreflection).
std::vector<std::string> default_models();

// Splits a list of model specs separated by ',' or ';' (items trimmed of spaces and tabs): an item of the
// form key=value (no ':' before its '=', no '+') continues the previous model's parameters, so
// "lambert,ggx:alpha=0.2,f0=0.04" is two models. Empty items are kept (the caller refuses them).
std::vector<std::string> split_model_list(const std::string& text);

struct SweepConfig {
  std::vector<int> levels, orders;   // ascending
  std::vector<std::string> models;   // canonical model specs (parse_model(spec).spec())
  std::vector<std::string> labels;   // the same models as given (shorter: defaults omitted), for tables and figures
  int threads = 1;
  int held_out = kDefaultHeldOutPairs;
  bool quick = false;
  LutSampling sampling = LutSampling::CellCentre;  // LUT rows and B sampled alike (build_fitting_grid)
  double gram_tolerance = 0.1;
};

struct ModelCell {
  double project_seconds, error_l2, error_max, error_l2_cosine;  // NaN when not fitted
};

struct SweepRow {
  int level = 0, order = 0;
  std::int64_t cells = 0;
  int modes = 0;
  bool supported = false;
  double gram_error = 0.0, condition = 0.0;
  double grid_seconds = 0.0, basis_seconds = 0.0, operator_seconds = 0.0;
  double reconstruct_seconds = 0.0, pairs_seconds = 0.0;  // NaN when not measured
  std::int64_t basis_bytes = 0, projection_bytes = 0, lut_bytes = 0, peak_rss_bytes = 0;
  std::vector<ModelCell> models;  // one per config.models
};

struct LevelSupport {
  int level = 0;
  std::int64_t cells = 0;
  int largest_order = -1;  // largest order <= kSupportSearchOrder with Gram error <= tolerance (-1: none)
  double gram_error_at_largest = 0.0;
};

struct SweepResult {
  SweepConfig config;
  Machine machine;
  std::string created;       // UTC ISO 8601
  std::string command_line;  // as typed
  std::vector<SweepRow> rows;
  std::vector<LevelSupport> support;
  std::map<std::string, ReportSection> sections;  // by section name (icobrdf/lab/report_section.hpp)
  double table_seconds = 0.0, sections_seconds = 0.0;
};

// Runs the level x order table and measures the GEMM rate, the FP64 peak and the bandwidth of result.machine. `progress` (may be empty)
// gets one line per finished row.
void measure_table(SweepResult& result, const std::function<void(const std::string&)>& progress);

// Runs every report section (icobrdf/lab/report_section.hpp) with the sweep's levels, orders,
// threads, quick flag and report folder.
void run_sections(SweepResult& result, const std::string& report_dir, const std::function<void(const std::string&)>& progress);

// Points of one model not dominated in (project_seconds, error_l2): no other supported row is at least as
// fast and at least as accurate and strictly better in one. Row indices, ascending time.
std::vector<std::size_t> pareto_front(const SweepResult& r, std::size_t model);

}  // namespace icobrdf::lab::sweep
