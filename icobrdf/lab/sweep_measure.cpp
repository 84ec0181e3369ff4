#include "icobrdf/lab/sweep_measure.hpp"

#include <fmt/core.h>
#include <omp.h>

#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <memory>
#include <numeric>
#include <random>

#include "icobrdf/core/models/brdf_model.hpp"
#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/projection/discrete_basis.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/projection/projection.hpp"
#include "icobrdf/core/fit/spectral_fit.hpp"
#include "icobrdf/core/spectrum/spectrum_ops.hpp"
#include "icobrdf/lab/process_usage.hpp"
#include "icobrdf/lab/timing.hpp"
#include "icobrdf/mesh/tessellation.hpp"

namespace icobrdf::lab::sweep {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Side of the square matrices of the GEMM whose rate is reported beside the theoretical peak.
constexpr int kGemmSize = 1024, kQuickGemmSize = 256;

// Best wall-clock time of f: once, or up to kTimingRepeats times when a run is shorter than kRepeatBelowSeconds.
template <class F>
double timed(F&& f) {
  return seconds_repeating_below(kRepeatBelowSeconds, kTimingRepeats, f);
}

std::int64_t peak_rss_bytes() { return static_cast<std::int64_t>(peak_resident_bytes()); }  // whole KiB: exact in a double

struct HeldOut {
  RowMatrix3d wi, wr;
};

HeldOut held_out_pairs(int n) {
  HeldOut h;
  h.wi.resize(n, 3);
  h.wr.resize(n, 3);
  std::mt19937_64 rng(kHeldOutSeed);
  for (int k = 0; k < n; ++k) {
    h.wi.row(k) = uniform_direction(rng).transpose();
    h.wr.row(k) = uniform_direction(rng).transpose();
  }
  return h;
}

// The exact model at the held-out pairs (pairs x channels) and the weights of the cosine metric.
struct Reference {
  Eigen::MatrixXd f;
  double norm = 0.0, max = 0.0, cos_norm = 0.0;
};

Reference reference_values(const BrdfModel& model, const HeldOut& h, const Eigen::VectorXd& cosw) {
  Reference r;
  r.f.resize(h.wi.rows(), model.channels());
  model.eval(h.wi, h.wr, r.f);
  r.norm = r.f.norm();
  r.max = r.f.cwiseAbs().maxCoeff();
  r.cos_norm = (cosw.asDiagonal() * r.f).norm();
  return r;
}

// Relative errors of a spectrum's reconstruction K(w_i)^T C K(w_r) against the reference (all channels).
ModelCell errors_of(const Spectrum& s, const HeldOut& h, const Reference& ref, const Eigen::VectorXd& cosw) {
  double sq = 0.0, mx = 0.0, csq = 0.0;
  for (int ch = 0; ch < s.channel_count(); ++ch) {
    const Eigen::VectorXd fit = evaluate_coefficients(s.channels[ch], s.order, h.wi, h.wr);
    const Eigen::VectorXd d = fit - ref.f.col(ch);
    sq += d.squaredNorm();
    mx = std::max(mx, d.cwiseAbs().maxCoeff());
    csq += cosw.cwiseProduct(d).squaredNorm();
  }
  const auto rel = [](double num, double den) { return den > 0 ? num / den : num; };
  return {kNaN, rel(std::sqrt(sq), ref.norm), rel(mx, ref.max), rel(std::sqrt(csq), ref.cos_norm)};
}

}  // namespace

std::vector<std::string> split_model_list(const std::string& text) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = text.find_first_of(",;", start);
    std::string item = text.substr(start, end == std::string::npos ? std::string::npos : end - start);
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    const auto eq = item.find('='), colon = item.find(':');
    const bool continues = !out.empty() && eq != std::string::npos && (colon == std::string::npos || colon > eq) &&
                           item.find('+') == std::string::npos;
    if (continues) out.back() += "," + item;
    else out.push_back(item);
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return out;
}

std::vector<std::string> default_models() {
  return {"lambert", "oren-nayar:sigma=20", "minnaert:k=1.5", "lafortune:cx=1,cy=1,cz=1,n=20",
          "ggx:alpha=0.5", "ggx:alpha=0.2", "ggx:alpha=0.1", "ggx:alpha=0.05"};
}

namespace {

// The models of a sweep, their exact values at the held-out pairs and the weights of the cosine metric.
struct Truth {
  std::vector<std::unique_ptr<BrdfModel>> models;
  HeldOut held;
  Eigen::VectorXd cosw;
  std::vector<Reference> refs;
};

// The order a level supports: the leading Gram blocks of one basis of order kSupportSearchOrder.
LevelSupport level_support(int level, const Grid& grid, double gram_tolerance) {
  const DiscreteBasis top = build_discrete_basis(grid, kSupportSearchOrder);
  LevelSupport s;
  s.level = level;
  s.cells = grid.cells();
  s.largest_order = largest_supported_order(top, gram_tolerance);
  if (s.largest_order >= 0) {
    const int m = hemisphere_basis_count(s.largest_order);
    s.gram_error_at_largest = (top.G.topLeftCorner(m, m) - Eigen::MatrixXd::Identity(m, m)).cwiseAbs().maxCoeff();
  }
  return s;
}

// Fits every model with the operators of `ctx` (timed) and measures its errors; then the reconstruction and
// pair evaluation of the first model's spectrum.
void fit_models(SweepRow& row, const ProjectionContext& ctx, const Truth& t, double gram_tolerance) {
  FitOptions opt;
  opt.order = row.order;
  opt.gram_tolerance = gram_tolerance;
  opt.sampling = LutSampling::CellAverage;  // over the fitting grid's cubature (one point per cell when centre)
  Spectrum first;
  for (std::size_t m = 0; m < t.models.size(); ++m) {
    Spectrum s;
    const double seconds = timed([&] { s = fit_model(*t.models[m], ctx, opt); });
    row.models[m] = errors_of(s, t.held, t.refs[m], t.cosw);
    row.models[m].project_seconds = seconds;
    if (m == 0) first = std::move(s);
  }
  if (t.models.empty()) return;
  const std::int64_t lut = static_cast<std::int64_t>(sizeof(double)) * row.cells * row.cells;
  if (lut <= kMaxReconstructLutBytes) {
    row.reconstruct_seconds = timed([&] { Eigen::MatrixXd f = reconstruct_lut(ctx.basis, first.channels[0]); });
    row.lut_bytes = lut;
  }
  row.pairs_seconds = timed([&] { Eigen::VectorXd v = evaluate_coefficients(first.channels[0], row.order, t.held.wi, t.held.wr); });
}

// One (level, order) row on the level's grid built in grid_seconds.
SweepRow measure_row(int level, int order, const std::shared_ptr<const Grid>& grid, double grid_seconds, const Truth& t,
                     double gram_tolerance) {
  SweepRow row;
  row.level = level;
  row.order = order;
  row.cells = grid->cells();
  row.modes = hemisphere_basis_count(order);
  row.grid_seconds = grid_seconds;
  row.reconstruct_seconds = row.pairs_seconds = kNaN;
  row.models.assign(t.models.size(), ModelCell{kNaN, kNaN, kNaN, kNaN});
  ProjectionContext ctx;
  ctx.grid = grid;
  row.basis_seconds = timed([&] { ctx.basis = build_discrete_basis(*grid, order); });
  row.gram_error = ctx.basis.gram_error;
  row.condition = ctx.basis.condition;
  row.basis_bytes = static_cast<std::int64_t>(sizeof(double)) * (ctx.basis.B.size() + ctx.basis.G.size() + ctx.basis.W.size());
  row.supported = row.gram_error <= gram_tolerance && std::isfinite(row.condition);
  if (row.supported) {
    row.operator_seconds = timed([&] { ctx.projection = make_projection(ctx.basis); });
    row.projection_bytes = static_cast<std::int64_t>(sizeof(double)) * ctx.projection.P.size();
    fit_models(row, ctx, t, gram_tolerance);
  } else {
    row.operator_seconds = kNaN;
  }
  row.peak_rss_bytes = peak_rss_bytes();
  return row;
}

}  // namespace

void measure_table(SweepResult& result, const std::function<void(const std::string&)>& progress) {
  const SweepConfig& cfg = result.config;
  const auto t_start = std::chrono::steady_clock::now();
  result.machine.gemm_gflops = measure_gemm_gflops(cfg.quick ? kQuickGemmSize : kGemmSize);
  result.machine.measured_peak_gflops = measure_fp64_peak_gflops(cfg.threads);
  result.machine.bandwidth_gbs = measure_bandwidth_gbs(cfg.threads);
  Truth t;
  for (const auto& spec : cfg.models) t.models.push_back(parse_model(spec));
  t.held = held_out_pairs(cfg.held_out);
  t.cosw = t.held.wi.col(2).cwiseProduct(t.held.wr.col(2));
  for (const auto& m : t.models) t.refs.push_back(reference_values(*m, t.held, t.cosw));
  const bool centre = cfg.sampling == LutSampling::CellCentre;

  for (int level : cfg.levels) {
    std::shared_ptr<const Grid> grid;
    const double grid_seconds = timed([&] { grid = std::make_shared<const Grid>(build_fitting_grid(level, GridKind::EqualArea, centre)); });
    result.support.push_back(level_support(level, *grid, cfg.gram_tolerance));
    for (int order : cfg.orders) {
      const auto t_row = std::chrono::steady_clock::now();
      const SweepRow row = measure_row(level, order, grid, grid_seconds, t, cfg.gram_tolerance);
      result.rows.push_back(row);
      if (progress)
        progress(fmt::format("level {} order {:2d}: {} cells, {} modes, Gram error {:.2e}{}, {:.2f} s", level, order, row.cells, row.modes,
                             row.gram_error, row.supported ? "" : " (unsupported)",
                             std::chrono::duration<double>(std::chrono::steady_clock::now() - t_row).count()));
    }
  }
  result.table_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
}

void run_sections(SweepResult& result, const std::string& report_dir, const std::function<void(const std::string&)>& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  SectionOptions o;
  o.levels = result.config.levels;
  o.orders = result.config.orders;
  o.threads = result.config.threads;
  o.quick = result.config.quick;
  o.report_dir = report_dir;
  for (const auto& [name, run] : report_sections()) {
    const double s = seconds_of([&, n = name, r = run] { result.sections[n] = r(o); });
    if (progress) progress(fmt::format("section {}: {:.2f} s", name, s));
  }
  result.sections_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  result.machine.load_after = load_average();
}

std::vector<std::size_t> pareto_front(const SweepResult& r, std::size_t model) {
  std::vector<std::size_t> idx;
  for (std::size_t k = 0; k < r.rows.size(); ++k) {
    const ModelCell& c = r.rows[k].models.at(model);
    if (r.rows[k].supported && std::isfinite(c.project_seconds) && std::isfinite(c.error_l2)) idx.push_back(k);
  }
  std::stable_sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) {
    const ModelCell &x = r.rows[a].models[model], &y = r.rows[b].models[model];
    return x.project_seconds != y.project_seconds ? x.project_seconds < y.project_seconds : x.error_l2 < y.error_l2;
  });
  std::vector<std::size_t> front;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t k : idx) {
    const double e = r.rows[k].models[model].error_l2;
    if (e < best) {
      front.push_back(k);
      best = e;
    }
  }
  return front;
}

}  // namespace icobrdf::lab::sweep
