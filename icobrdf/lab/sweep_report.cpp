#include "icobrdf/lab/sweep_report.hpp"

#include <fmt/core.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "icobrdf/io/atomic_write.hpp"
#include "icobrdf/io/h5_file.hpp"
#include "icobrdf/io/scene.hpp"
#include "icobrdf/lab/order_chart.hpp"
#include "icobrdf/lab/report_format.hpp"
#include "icobrdf/plot/line_chart.hpp"

namespace icobrdf::lab::sweep {
namespace {

// Figure sizes: readable at report width, small PNGs (tens of KB).
constexpr int kFigureWidth = 720, kFigureHeight = 440;
// Errors and Gram errors are drawn no lower than this on log axes: an exact 0 (Lambert's fit, order 0's
// Gram error) would otherwise vanish; 1e-16 is about the rounding of double sums (eps / 2 = 1.1e-16).
constexpr double kPlotFloor = 1e-16;

double floored(double v) { return std::isfinite(v) ? std::max(v, kPlotFloor) : v; }

std::string mib(std::int64_t bytes) { return bytes > 0 ? fmt::format("{:.1f}", bytes / 1048576.0) : "-"; }
std::string secs(double s) { return std::isfinite(s) ? sci(s) : "-"; }

// Rows of one level, in order.
std::vector<const SweepRow*> rows_of_level(const SweepResult& r, int level) {
  std::vector<const SweepRow*> v;
  for (const auto& row : r.rows)
    if (row.level == level) v.push_back(&row);
  return v;
}

std::string level_note(const SweepResult& r) {
  return fmt::format("{} held-out pairs (seed {}), {} sampling, Gram tolerance {}", r.config.held_out, kHeldOutSeed, to_string(r.config.sampling),
                     r.config.gram_tolerance);
}

// One chart series per level of the sweep: y(row) against the order.
template <class Y>
std::vector<plot::Series> series_per_level(const SweepResult& r, Y y) {
  std::vector<plot::Series> series;
  for (int level : r.config.levels) {
    plot::Series s;
    s.label = fmt::format("level {}", level);
    for (const SweepRow* row : rows_of_level(r, level)) {
      s.x.push_back(row->order);
      s.y.push_back(y(*row));
    }
    series.push_back(std::move(s));
  }
  return series;
}

}  // namespace

std::string model_slug(const std::string& spec) {
  std::string s;
  for (char c : spec) {
    const bool keep = std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-';
    if (keep) s += c;
    else if (s.empty() || s.back() != '_') s += '_';
  }
  while (!s.empty() && s.back() == '_') s.pop_back();
  return s.empty() ? "model" : s;
}

std::vector<std::string> draw_figures(const SweepResult& r, const std::string& dir) {
  using namespace icobrdf::plot;
  std::vector<std::string> files;
  const auto& cfg = r.config;
  // Error vs order, one figure per model, one series per level.
  for (std::size_t m = 0; m < cfg.models.size(); ++m) {
    std::vector<Series> series = series_per_level(
        r, [m](const SweepRow& row) { return row.supported ? floored(row.models[m].error_l2) : std::nan(""); });
    ChartOptions o = order_chart("Relative L2 error at held-out pairs: " + cfg.labels[m], "relative L2 error");
    o.width = kFigureWidth;
    o.height = kFigureHeight;
    o.note = level_note(r) + "; unsupported orders omitted; floor 1e-16";
    const std::string name = "sweep_error_" + model_slug(cfg.labels[m]) + ".png";
    draw_line_chart(series, o, dir + "/" + name);
    files.push_back(name);
  }
  // Time vs error: the Pareto front of each model.
  {
    std::vector<Series> series;
    for (std::size_t m = 0; m < cfg.models.size(); ++m) {
      Series s;
      s.label = cfg.labels[m];
      for (std::size_t k : pareto_front(r, m)) {
        s.x.push_back(r.rows[k].models[m].project_seconds);
        s.y.push_back(floored(r.rows[k].models[m].error_l2));
      }
      series.push_back(std::move(s));
    }
    ChartOptions o;
    o.title = "Projection time against error (Pareto front per model)";
    o.x_label = "seconds to project one material (operators built)";
    o.y_label = "relative L2 error";
    o.log_x = o.log_y = true;
    o.width = kFigureWidth + 120;
    o.height = kFigureHeight;
    o.note = fmt::format("{} thread(s); (level, order) pairs no other pair beats in both time and error; errors floored at 1e-16", cfg.threads);
    draw_line_chart(series, o, dir + "/sweep_pareto.png");
    files.push_back("sweep_pareto.png");
  }
  // Gram error vs order, one series per level, and the tolerance.
  {
    std::vector<Series> series = series_per_level(r, [](const SweepRow& row) { return floored(row.gram_error); });
    Series tol;
    tol.label = fmt::format("tolerance {}", cfg.gram_tolerance);
    tol.x = {static_cast<double>(cfg.orders.front()), static_cast<double>(cfg.orders.back())};
    tol.y = {cfg.gram_tolerance, cfg.gram_tolerance};
    tol.colour = {0.35, 0.35, 0.35};
    tol.dashed = true;
    tol.marker = plot::Marker::None;
    tol.line_width = 1.2;
    series.push_back(tol);
    ChartOptions o = order_chart("Gram error max|G - I| against order", "Gram error");
    o.width = kFigureWidth;
    o.height = kFigureHeight;
    o.note = fmt::format("{} sampling; a pair above the tolerance is unsupported (not fitted); values below 1e-16 drawn at 1e-16", to_string(cfg.sampling));
    draw_line_chart(series, o, dir + "/sweep_gram.png");
    files.push_back("sweep_gram.png");
  }
  return files;
}

namespace {

// Title, provenance, machine and configuration, and how errors and times are measured.
std::string header_markdown(const SweepResult& r) {
  const auto& cfg = r.config;
  const auto& mc = r.machine;
  std::string md = "# Speed against error: `icobrdf bench sweep`\n\n";
  md += fmt::format("- date: {}\n- command: `{}`\n", r.created, r.command_line);
  md += fmt::format("- machine: {}, {} cores, SIMD {}, kernels dispatched to {}, clock {:.0f} MHz; FP64 peak for {} thread(s): "
                    "measured {:.1f} GFLOP/s (FMA throughput, as `bench project`), nominal {:.1f} ({} flops/cycle/core x clock); "
                    "measured Eigen 1024^3 GEMM {:.1f} GFLOP/s = {:.2f} of the measured peak; memory bandwidth {:.1f} GB/s (triad)\n",
                    mc.cpu_model, mc.cores, mc.isa, mc.simd_target, mc.cpu_mhz, cfg.threads, mc.measured_peak_gflops, mc.peak_gflops,
                    mc.flops_per_cycle_per_core, mc.gemm_gflops, mc.measured_peak_gflops > 0 ? mc.gemm_gflops / mc.measured_peak_gflops : 0.0,
                    mc.bandwidth_gbs);
  md += fmt::format("- load average before: {}; after: {}\n", mc.load_before, mc.load_after);
  md += fmt::format("- levels {}; orders {}; models (canonical specs): {}\n", fmt::join(cfg.levels, ","), fmt::join(cfg.orders, ","),
                    fmt::join(cfg.models, "; "));
  md += fmt::format("- {}; grid equal-area (`build_fitting_grid`)\n", level_note(r));
  md += fmt::format("- run time: table {:.1f} s, report sections {:.1f} s\n\n", r.table_seconds, r.sections_seconds);
  md += "Errors are those of the reconstructed BRDF K(w_i)^T C K(w_r) against the exact model at held-out pairs "
        "(both directions uniform in solid angle): relative L2 = ||f_fit - f|| / ||f||, relative max = max|f_fit - f| / max|f|. "
        "Times are wall-clock seconds (best of up to 5 runs for steps under 50 ms); projection is `fit_model` "
        "(streaming, no LUT) with the operators already built.\n\n";
  return md;
}

std::string support_markdown(const SweepResult& r) {
  const auto& cfg = r.config;
  std::string md;
  md += "## Order each level supports\n\n";
  std::vector<std::vector<std::string>> rows;
  for (const auto& s : r.support)
    rows.push_back({std::to_string(s.level), std::to_string(s.cells),
                    s.largest_order >= kSupportSearchOrder ? fmt::format(">= {}", kSupportSearchOrder) : std::to_string(s.largest_order),
                    s.largest_order >= 0 ? sci(s.gram_error_at_largest) : "-"});
  md += fmt::format("Largest order N <= {} whose Gram error max|G - I| is within the tolerance {}:\n\n", kSupportSearchOrder,
                    cfg.gram_tolerance);
  md += md_table({"level", "cells", "largest supported order", "Gram error there"}, rows);
  return md;
}

std::string grid_markdown(const SweepResult& r) {
  std::string md;
  md += "## Grid and operators per (level, order)\n\n";
  std::vector<std::vector<std::string>> rows;
  for (const auto& row : r.rows)
    rows.push_back({std::to_string(row.level), std::to_string(row.order), std::to_string(row.cells), std::to_string(row.modes),
                    sci(row.gram_error), sci(row.condition), row.supported ? "yes" : "**no**", secs(row.grid_seconds),
                    secs(row.basis_seconds), secs(row.operator_seconds), secs(row.reconstruct_seconds), secs(row.pairs_seconds),
                    mib(row.basis_bytes), mib(row.projection_bytes), mib(row.lut_bytes), mib(row.peak_rss_bytes)});
  md += "Seconds: grid = build the level's fitting grid; B = basis, Gram matrix and its condition; P = projection operator; "
        "reconstruct = B C B^T (the full LUT, `-` when larger than " +
        mib(kMaxReconstructLutBytes) + " MiB); pairs = evaluate one spectrum at the held-out pairs. Memory in MiB; "
        "peak RSS is the process's peak so far.\n\n";
  md += md_table({"level", "order", "cells", "modes", "Gram error", "condition", "supported", "grid s", "B s", "P s", "reconstruct s",
                  "pairs s", "B MiB", "P MiB", "LUT MiB", "peak RSS MiB"},
                 rows);
  return md;
}

// A table of one value per (supported order, model) of a level; a sentence when no order is supported.
template <class Value>
std::string per_model_table(const SweepResult& r, int level, Value value) {
  const auto& cfg = r.config;
  std::vector<std::string> header{"order"};
  for (const auto& m : cfg.labels) header.push_back("`" + m + "`");
  std::vector<std::vector<std::string>> rows;
  for (const SweepRow* row : rows_of_level(r, level)) {
    if (!row->supported) continue;
    std::vector<std::string> cells{std::to_string(row->order)};
    for (std::size_t m = 0; m < cfg.models.size(); ++m) cells.push_back(value(row->models[m]));
    rows.push_back(cells);
  }
  if (rows.empty()) return fmt::format("Level {}: no swept order is supported.\n\n", level);
  return md_table(header, rows);
}

std::string errors_markdown(const SweepResult& r) {
  const auto& cfg = r.config;
  std::string md;
  md += "## Relative L2 error against order\n\n";
  for (int level : cfg.levels) {
    md += fmt::format("### Level {}\n\n", level);
    md += per_model_table(r, level, [](const ModelCell& c) { return sci(c.error_l2); });
  }
  md += "## Relative max error and projection time\n\n";
  for (int level : cfg.levels) {
    md += fmt::format("<details><summary>Level {}: relative max error, cosine-weighted L2 error, seconds to project</summary>\n\n", level);
    md += "Relative max error:\n\n" + per_model_table(r, level, [](const ModelCell& c) { return sci(c.error_max); });
    md += "Relative L2 error of cos(theta_i) cos(theta_r) f:\n\n" + per_model_table(r, level, [](const ModelCell& c) { return sci(c.error_l2_cosine); });
    md += "Seconds to project one material:\n\n" + per_model_table(r, level, [](const ModelCell& c) { return secs(c.project_seconds); });
    md += "</details>\n\n";
  }
  return md;
}

std::string pareto_markdown(const SweepResult& r) {
  const auto& cfg = r.config;
  std::string md;
  md += "## Pareto front of time against error\n\n";
  md += "Per model, the (level, order) pairs that no other pair beats in both projection time and relative L2 error, fastest first.\n\n";
  std::vector<std::vector<std::string>> rows;
  for (std::size_t m = 0; m < cfg.models.size(); ++m) {
    std::string pts;
    for (std::size_t k : pareto_front(r, m)) {
      const auto& row = r.rows[k];
      if (!pts.empty()) pts += "; ";
      pts += fmt::format("L{} N{}: {} s, {}", row.level, row.order, secs(row.models[m].project_seconds), sci(row.models[m].error_l2));
    }
    rows.push_back({"`" + cfg.labels[m] + "`", pts.empty() ? "-" : pts});
  }
  md += md_table({"model", "front (level, order: seconds, relative L2 error)"}, rows);
  return md;
}

}  // namespace

std::string report_markdown(const SweepResult& r, const std::vector<std::string>& figures) {
  std::string md = header_markdown(r) + support_markdown(r) + grid_markdown(r) + errors_markdown(r) + pareto_markdown(r);
  md += "## Figures\n\n";
  for (const auto& f : figures) md += fmt::format("![{}]({})\n\n", f, f);

  for (const auto& [name, s] : r.sections) {
    md += "## " + s.title + "\n\n";
    md += s.markdown;
    if (!md.empty() && md.back() != '\n') md += "\n";
    md += "\n";
  }
  return md;
}

nlohmann::json to_json(const SweepResult& r) {
  using nlohmann::json;
  const auto& cfg = r.config;
  json j;
  j["format"] = kSweepFormat;
  j["format_version"] = kSweepFormatVersion;
  j["created"] = r.created;
  j["command"] = r.command_line;
  const auto& mc = r.machine;
  j["machine"] = {{"cpu_model", mc.cpu_model}, {"cores", mc.cores}, {"isa", mc.isa}, {"cpu_mhz", mc.cpu_mhz},
                  {"flops_per_cycle_per_core", mc.flops_per_cycle_per_core}, {"peak_gflops", mc.peak_gflops},
                  {"measured_peak_gflops", mc.measured_peak_gflops}, {"simd_target", mc.simd_target}, {"bandwidth_gbs", mc.bandwidth_gbs},
                  {"gemm_gflops", mc.gemm_gflops}, {"load_before", mc.load_before}, {"load_after", mc.load_after}};
  j["config"] = {{"levels", cfg.levels}, {"orders", cfg.orders}, {"models", cfg.models}, {"labels", cfg.labels}, {"threads", cfg.threads},
                 {"held_out_pairs", cfg.held_out}, {"held_out_seed", kHeldOutSeed}, {"quick", cfg.quick},
                 {"sampling", to_string(cfg.sampling)}, {"gram_tolerance", cfg.gram_tolerance}};
  j["table_seconds"] = r.table_seconds;
  j["sections_seconds"] = r.sections_seconds;
  json support = json::array();
  for (const auto& s : r.support)
    support.push_back({{"level", s.level}, {"cells", s.cells}, {"largest_order", s.largest_order},
                       {"search_order", kSupportSearchOrder}, {"gram_error", num(s.gram_error_at_largest)}});
  j["support"] = support;
  json rows = json::array();
  for (const auto& row : r.rows) {
    json models = json::array();
    for (std::size_t m = 0; m < row.models.size(); ++m) {
      const auto& c = row.models[m];
      models.push_back({{"model", cfg.models[m]}, {"label", cfg.labels[m]}, {"project_seconds", num(c.project_seconds)}, {"error_l2", num(c.error_l2)},
                        {"error_max", num(c.error_max)}, {"error_l2_cosine", num(c.error_l2_cosine)}});
    }
    rows.push_back({{"level", row.level}, {"order", row.order}, {"cells", row.cells}, {"modes", row.modes},
                    {"supported", row.supported}, {"gram_error", num(row.gram_error)}, {"condition", num(row.condition)},
                    {"grid_seconds", num(row.grid_seconds)}, {"basis_seconds", num(row.basis_seconds)},
                    {"operator_seconds", num(row.operator_seconds)}, {"reconstruct_seconds", num(row.reconstruct_seconds)},
                    {"pairs_seconds", num(row.pairs_seconds)}, {"basis_bytes", row.basis_bytes},
                    {"projection_bytes", row.projection_bytes}, {"lut_bytes", row.lut_bytes},
                    {"peak_rss_bytes", row.peak_rss_bytes}, {"models", models}});
  }
  j["rows"] = rows;
  json pareto = json::object();
  for (std::size_t m = 0; m < cfg.models.size(); ++m) {
    json pts = json::array();
    for (std::size_t k : pareto_front(r, m))
      pts.push_back({{"level", r.rows[k].level}, {"order", r.rows[k].order},
                     {"project_seconds", r.rows[k].models[m].project_seconds}, {"error_l2", r.rows[k].models[m].error_l2}});
    pareto[cfg.models[m]] = pts;
  }
  j["pareto"] = pareto;
  json sections = json::object();
  for (const auto& [name, s] : r.sections) sections[name] = {{"title", s.title}, {"figures", s.figures}, {"data", s.data}};
  j["sections"] = sections;
  return j;
}

namespace {

template <class T, class F>
void column(h5::Group& g, const std::string& name, const std::vector<SweepRow>& rows, F get, const std::string& unit,
            const std::string& description) {
  std::vector<T> v;
  for (const auto& row : rows) v.push_back(static_cast<T>(get(row)));
  g.write(name, v.data(), {static_cast<std::uint64_t>(v.size())}, unit, description);
}

template <class F>
void model_column(h5::Group& g, const std::string& name, const SweepResult& r, F get, const std::string& unit,
                  const std::string& description) {
  const std::size_t nm = r.config.models.size();
  std::vector<double> v;
  for (const auto& row : r.rows)
    for (std::size_t m = 0; m < nm; ++m) v.push_back(get(row.models[m]));
  g.write(name, v.data(), {static_cast<std::uint64_t>(r.rows.size()), static_cast<std::uint64_t>(nm)}, unit, description);
}

void text_dataset(h5::Group& g, const std::string& name, const std::string& text, const std::string& description) {
  std::vector<std::uint8_t> bytes(text.begin(), text.end());
  g.write(name, bytes.data(), {static_cast<std::uint64_t>(bytes.size())}, "utf-8", description);
}

// Root attributes: format, provenance and the configuration.
void write_root_attrs(h5::Group& root, const SweepResult& r, const nlohmann::json& j) {
  const auto& cfg = r.config;
  root.set_attr("format", kSweepFormat);
  root.set_attr("format_version", kSweepFormatVersion);
  root.set_attr("creator", std::string("icobrdf ") + ICOBRDF_VERSION);
  root.set_attr("created", r.created);
  root.set_attr("command", r.command_line);
  root.set_attr("machine", j["machine"].dump());
  root.set_attr("config", j["config"].dump());
  root.set_attr("grid_kind", "equal-area");
  root.set_attr("sampling", to_string(cfg.sampling));
  root.set_attr("gram_tolerance", cfg.gram_tolerance);
  root.set_attr("held_out_pairs", static_cast<std::int32_t>(cfg.held_out));
  root.set_attr("held_out_seed", static_cast<std::int64_t>(kHeldOutSeed));
  root.set_attr("threads", static_cast<std::int32_t>(cfg.threads));
  root.set_attr("table_seconds", r.table_seconds);
  root.set_attr("sections_seconds", r.sections_seconds);
}

// /table: one dataset per row column, rows x models datasets per model column, and the Pareto flags.
void write_table(h5::Group& root, const SweepResult& r) {
  const auto& cfg = r.config;
  h5::Group t = root.create_group("table");
  t.set_attr("rows", static_cast<std::int64_t>(r.rows.size()));
  t.set_attr("models", nlohmann::json(cfg.models).dump());
  t.set_attr("labels", nlohmann::json(cfg.labels).dump());
  const auto& rows = r.rows;
  column<std::int32_t>(t, "level", rows, [](const SweepRow& x) { return x.level; }, "1", "tessellation level L");
  column<std::int32_t>(t, "order", rows, [](const SweepRow& x) { return x.order; }, "1", "expansion order N");
  column<std::int64_t>(t, "cells", rows, [](const SweepRow& x) { return x.cells; }, "1", "cells C = 10 4^L + 2^(L+1)");
  column<std::int32_t>(t, "modes", rows, [](const SweepRow& x) { return x.modes; }, "1", "modes M = (N+1)(N+2)/2");
  column<std::uint8_t>(t, "supported", rows, [](const SweepRow& x) { return x.supported ? 1 : 0; }, "1",
                       "1 when gram_error <= gram_tolerance and G is non-singular; 0: not fitted");
  column<double>(t, "gram_error", rows, [](const SweepRow& x) { return x.gram_error; }, "1", "max |G - I|");
  column<double>(t, "condition", rows, [](const SweepRow& x) { return x.condition; }, "1", "lambda_max(G) / lambda_min(G)");
  column<double>(t, "grid_seconds", rows, [](const SweepRow& x) { return x.grid_seconds; }, "s", "build the level's fitting grid");
  column<double>(t, "basis_seconds", rows, [](const SweepRow& x) { return x.basis_seconds; }, "s", "build B, G, Gram error and condition");
  column<double>(t, "operator_seconds", rows, [](const SweepRow& x) { return x.operator_seconds; }, "s",
                 "build P = W B G^-1; NaN when unsupported");
  column<double>(t, "reconstruct_seconds", rows, [](const SweepRow& x) { return x.reconstruct_seconds; }, "s",
                 "B C B^T of one spectrum; NaN when unsupported or the LUT is not materialized");
  column<double>(t, "pairs_seconds", rows, [](const SweepRow& x) { return x.pairs_seconds; }, "s",
                 "evaluate one spectrum at the held-out pairs; NaN when unsupported");
  column<std::int64_t>(t, "basis_bytes", rows, [](const SweepRow& x) { return x.basis_bytes; }, "byte", "B, W and G");
  column<std::int64_t>(t, "projection_bytes", rows, [](const SweepRow& x) { return x.projection_bytes; }, "byte", "P (0 when unsupported)");
  column<std::int64_t>(t, "lut_bytes", rows, [](const SweepRow& x) { return x.lut_bytes; }, "byte",
                       "reconstructed LUT (0 when not materialized)");
  column<std::int64_t>(t, "peak_rss_bytes", rows, [](const SweepRow& x) { return x.peak_rss_bytes; }, "byte",
                       "peak resident set of the process after the row");
  model_column(t, "project_seconds", r, [](const ModelCell& c) { return c.project_seconds; }, "s",
               "rows x models: fit_model of one material with the operators built; NaN when unsupported");
  model_column(t, "error_l2", r, [](const ModelCell& c) { return c.error_l2; }, "1",
               "rows x models: ||f_fit - f|| / ||f|| at the held-out pairs; NaN when unsupported");
  model_column(t, "error_max", r, [](const ModelCell& c) { return c.error_max; }, "1",
               "rows x models: max|f_fit - f| / max|f| at the held-out pairs; NaN when unsupported");
  model_column(t, "error_l2_cosine", r, [](const ModelCell& c) { return c.error_l2_cosine; }, "1",
               "rows x models: relative L2 error of cos(theta_i) cos(theta_r) f; NaN when unsupported");
  {
    std::vector<std::uint8_t> front(r.rows.size() * cfg.models.size(), 0);
    for (std::size_t m = 0; m < cfg.models.size(); ++m)
      for (std::size_t k : pareto_front(r, m)) front[k * cfg.models.size() + m] = 1;
    t.write("pareto", front.data(), {static_cast<std::uint64_t>(r.rows.size()), static_cast<std::uint64_t>(cfg.models.size())}, "1",
            "rows x models: 1 on the model's Pareto front of (project_seconds, error_l2)");
  }
}

// /support: the largest supported order per level.
void write_support(h5::Group& root, const SweepResult& r) {
  h5::Group s = root.create_group("support");
  std::vector<std::int32_t> lv, lo;
  std::vector<std::int64_t> cells;
  std::vector<double> ge;
  for (const auto& x : r.support) {
    lv.push_back(x.level);
    lo.push_back(x.largest_order);
    cells.push_back(x.cells);
    ge.push_back(x.largest_order >= 0 ? x.gram_error_at_largest : std::nan(""));
  }
  const h5::Shape shape{static_cast<std::uint64_t>(r.support.size())};
  s.set_attr("search_order", static_cast<std::int32_t>(kSupportSearchOrder));
  s.write("level", lv.data(), shape, "1", "tessellation level");
  s.write("cells", cells.data(), shape, "1", "cells of the level");
  s.write("largest_order", lo.data(), shape, "1", "largest order <= search_order within the Gram tolerance (-1: none)");
  s.write("gram_error", ge.data(), shape, "1", "max |G - I| at largest_order");
}

// /sections/<name>: each report section's title, figures, markdown and JSON data.
void write_sections(h5::Group& root, const SweepResult& r) {
  h5::Group secs_group = root.create_group("sections");
  for (const auto& [name, sec] : r.sections) {
    h5::Group g = secs_group.create_group(name);
    g.set_attr("title", sec.title);
    g.set_attr("figures", nlohmann::json(sec.figures).dump());
    text_dataset(g, "markdown", sec.markdown, "the section's markdown (UTF-8 bytes)");
    text_dataset(g, "data_json", sec.data.dump(), "the section's figures as JSON (UTF-8 bytes)");
  }
}

}  // namespace

void write_results_h5(const SweepResult& r, const std::string& path) {
  const nlohmann::json j = to_json(r);
  atomic_write(path, [&](const std::string& temp) {
    h5::WriteFile f = h5::WriteFile::create(temp, path);
    {
      h5::Group root = f.root();
      write_root_attrs(root, r, j);
      write_table(root, r);
      write_support(root, r);
      write_sections(root, r);
    }
    f.finish();
  });
}

nlohmann::json sweep_summary_json(const SweepResult& r, const std::string& output, const std::string& report_md,
                                  const std::vector<std::string>& figures) {
  nlohmann::json j = to_json(r);
  j["output"] = output;
  j["report"] = report_md;
  j["figures"] = figures;
  return j;
}

std::string sweep_summary_text(const SweepResult& r, const std::string& output, const std::string& report_md,
                               const std::vector<std::string>& figures) {
  std::string text = fmt::format("bench sweep: {} (level, order) pairs x {} models in {:.1f} s, report sections in {:.1f} s\n", r.rows.size(),
                                 r.config.models.size(), r.table_seconds, r.sections_seconds);
  for (const auto& s : r.support)
    text += fmt::format("  level {} ({} cells): supports order {}\n", s.level, s.cells,
                        s.largest_order >= kSupportSearchOrder ? ">= " + std::to_string(kSupportSearchOrder) : std::to_string(s.largest_order));
  return text + fmt::format("wrote {} and {} ({} sweep figures, {} sections)\n", output, report_md, figures.size(), r.sections.size());
}

}  // namespace icobrdf::lab::sweep
