#include "icobrdf/lab/baselines.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/grid/reference_grids.hpp"
#include "icobrdf/lab/direct_vs_matrix.hpp"
#include "icobrdf/lab/grid_comparison.hpp"
#include "icobrdf/lab/report_format.hpp"
#include "icobrdf/mesh/tessellation.hpp"
#include "icobrdf/plot/line_chart.hpp"

namespace icobrdf::lab {
namespace {

// Orders whose cell counts are reported.
constexpr int kNeededOrders[] = {4, 8, 12, 16};
// Floor of the log-scale figures: Gram errors of exact rules are rounding, shown at machine epsilon.
constexpr double kEps = std::numeric_limits<double>::epsilon();

using Rows = std::vector<std::vector<std::string>>;

// Orders in the tables: the requested ones up to max_order that are 2, 4, 8, 12, ... (all when few).
std::vector<int> shown_orders(const std::vector<int>& orders, int max_order) {
  std::vector<int> shown;
  for (int n : orders)
    if (n <= max_order && (orders.size() <= 8 || n == 2 || (n % 4 == 0 && n > 0))) shown.push_back(n);
  return shown;
}

// Runs of one grid kind, ascending cells.
std::vector<const GridRun*> family_of(const std::vector<GridRun>& runs, const std::string& kind) {
  std::vector<const GridRun*> family;
  for (const auto& r : runs)
    if (r.kind == kind) family.push_back(&r);
  std::sort(family.begin(), family.end(), [](const GridRun* a, const GridRun* b) { return a->cells < b->cells; });
  return family;
}

std::string intro(int max_order) {
  return fmt::format(
      "Every grid samples the hemisphere basis K up to order {} (B, cells x modes) and forms G = B^T W B; "
      "G = I for the continuous basis, so max|G - I| says how faithfully the grid represents each order. "
      "Equal-area and geodesic: the icosahedral cells of the level with their degree-{} cubature (cell averages), "
      "equal-area-centre: the same cells sampled at their centres (what `icobrdf fit` uses); lat-long: n x 4n "
      "cells uniform in theta and phi with {} x {} Gauss points each; polar-gauss: r Gauss-Legendre rings in "
      "rho^2 x 4r azimuths (one point per node, exact to order 2r - 1). Lat-long and polar-gauss are matched "
      "to the level's cell count.\n\n",
      max_order, kDefaultCubatureDegree, kLatLongPoints, kLatLongPoints);
}

std::string gram_and_condition_tables(const std::vector<GridRun>& runs, const std::vector<int>& shown) {
  std::vector<std::string> h = {"grid", "size", "cells", "points"};
  for (int n : shown) h.push_back("N=" + std::to_string(n));
  Rows gram_rows, cond_rows;
  for (const auto& kind : kGridKinds)
    for (const auto& r : runs) {
      if (r.kind != kind) continue;
      std::vector<std::string> a = {r.kind, r.size, std::to_string(r.cells), std::to_string(r.points)}, c = a;
      for (int n : shown) a.push_back(sci(r.gram[static_cast<size_t>(n)], 1));
      for (int n : shown) c.push_back(n > 0 ? sci(r.condition.at(n), 2) : "1");
      gram_rows.push_back(a);
      cond_rows.push_back(c);
    }
  return "### Gram error max|G - I| by order\n\n" + md_table(h, gram_rows) + "### Condition number of G by order\n\n" +
         md_table(h, cond_rows);
}

nlohmann::json runs_json(const std::vector<GridRun>& runs) {
  nlohmann::json jruns = nlohmann::json::array();
  for (const auto& r : runs) {
    nlohmann::json cond = nlohmann::json::object(), largest = nlohmann::json::object();
    for (const auto& [n, v] : r.condition) cond[std::to_string(n)] = num(v);
    for (size_t t = 0; t < std::size(kBaselineTolerances); ++t) largest[sci(kBaselineTolerances[t], 0)] = r.largest[t];
    nlohmann::json gram = nlohmann::json::array();
    for (double e : r.gram) gram.push_back(num(e));
    jruns.push_back({{"kind", r.kind},
                     {"size", r.size},
                     {"level", r.level},
                     {"cells", r.cells},
                     {"rings", r.rings},
                     {"azimuths", r.azimuths},
                     {"points", r.points},
                     {"grid_seconds", r.grid_seconds},
                     {"basis_seconds", r.basis_seconds},
                     {"gram_error", gram},
                     {"condition", cond},
                     {"largest_supported_order", largest}});
  }
  return jruns;
}

// Gram error against cells, one log-log chart per order of kNeededOrders; returns the file names.
std::vector<std::string> draw_gram_figures(const std::vector<GridRun>& runs, int max_order, const std::filesystem::path& dir) {
  std::vector<std::string> files;
  for (int n : kNeededOrders) {
    if (n > max_order) continue;
    std::vector<plot::Series> series;
    for (const auto& kind : kGridKinds) {
      plot::Series sr;
      sr.label = kind;
      for (const auto& r : runs)
        if (r.kind == kind) {
          sr.x.push_back(r.cells);
          sr.y.push_back(std::max(r.gram[static_cast<size_t>(n)], kEps));
        }
      series.push_back(sr);
    }
    plot::ChartOptions co;
    co.title = fmt::format("Gram error vs cells, order {}", n);
    co.x_label = "cells";
    co.y_label = "max|G - I|";
    co.log_x = co.log_y = true;
    co.note = "values below machine epsilon shown at epsilon (exact rules)";
    const std::string file = fmt::format("baselines_gram_vs_cells_N{}.png", n);
    plot::draw_line_chart(series, co, (dir / file).string());
    files.push_back(file);
  }
  return files;
}

std::string largest_order_table(const std::vector<GridRun>& runs, int max_order) {
  std::vector<std::string> h = {"grid", "size", "cells"};
  for (double t : kBaselineTolerances) h.push_back("tol " + sci(t, 0));
  Rows rows;
  for (const auto& kind : kGridKinds)
    for (const auto& r : runs) {
      if (r.kind != kind) continue;
      std::vector<std::string> a = {r.kind, r.size, std::to_string(r.cells)};
      for (size_t t = 0; t < std::size(kBaselineTolerances); ++t)
        a.push_back(r.largest[t] == max_order ? ">= " + std::to_string(max_order) : std::to_string(r.largest[t]));
      rows.push_back(a);
    }
  return fmt::format("### Largest order supported at a Gram tolerance (orders <= {} measured)\n\n", max_order) + md_table(h, rows);
}

// One cell of the "cells needed" table and its JSON record.
std::string cells_needed_cell(const std::string& kind, const std::vector<const GridRun*>& family, int n, double tol, nlohmann::json& jneed) {
  if (kind == to_string(GridKind::PolarGauss)) {
    const PolarSearch ps = polar_gauss_search(n, tol);
    jneed.push_back({{"kind", kind}, {"tolerance", tol}, {"order", n}, {"cells", ps.cells}, {"rings", ps.rings},
                     {"azimuths", 2 * n + 1}, {"gram_error", ps.gram}, {"gram_error_one_ring_less", num(ps.gram_one_ring_less)},
                     {"exactness_rings", (n + 2) / 2}});
    return ps.rings > 0 ? fmt::format("{} ({} x {})", ps.cells, ps.rings, 2 * n + 1) : "not found";
  }
  const CellsNeeded c = cells_needed(family, n, tol);
  std::string cell = c.smallest_built < 0 ? "> " + std::to_string(family.back()->cells) : std::to_string(c.smallest_built);
  if (std::isfinite(c.interpolated)) cell += fmt::format(" (~{:.0f})", c.interpolated);
  jneed.push_back({{"kind", kind}, {"tolerance", tol}, {"order", n}, {"smallest_built_cells", c.smallest_built},
                   {"interpolated_cells", num(c.interpolated)}});
  return cell;
}

std::string cells_needed_table(const std::vector<GridRun>& runs, int max_order, nlohmann::json& jneed) {
  std::vector<std::string> h = {"grid", "tolerance"};
  std::vector<int> orders;
  for (int n : kNeededOrders)
    if (n <= max_order) orders.push_back(n);
  for (int n : orders) h.push_back("N=" + std::to_string(n));
  Rows rows;
  jneed = nlohmann::json::array();
  for (const auto& kind : kGridKinds) {
    const std::vector<const GridRun*> family = family_of(runs, kind);
    for (double tol : kBaselineTolerances) {
      std::vector<std::string> a = {kind, sci(tol, 0)};
      for (int n : orders) a.push_back(cells_needed_cell(kind, family, n, tol, jneed));
      rows.push_back(a);
    }
  }
  return "### Cells needed for a Gram error\n\n"
         "Smallest built size meeting the tolerance, with the log-log interpolation between it and the size "
         "before in parentheses (the Gram error of cell averages falls as a power of the cell size). "
         "Polar-gauss: the smallest ring count r found by search with 2N + 1 azimuths (exactness predicts "
         "r = floor(N/2) + 1), cells = r (2N + 1).\n\n" +
         md_table(h, rows);
}

std::string direct_section(const SectionOptions& o, nlohmann::json& jd) {
  const std::vector<DirectCase> cases = o.quick ? std::vector<DirectCase>{{2, 4}, {3, 6}} : std::vector<DirectCase>{{3, 6}, {4, 8}};
  std::vector<std::vector<std::string>> rows;
  jd = nlohmann::json::array();
  for (const auto& dc : cases) {
    std::vector<std::string> row;
    jd.push_back(direct_vs_matrix(dc, row));
    rows.push_back(row);
  }
  return fmt::format(
             "### Direct quadrature without matrices vs the matrix path\n\n"
             "Model `{}`, equal-area cells sampled at their centres, {} thread(s), best of {} runs. Matrix: B, G and P = W B G^-1 built "
             "once, then C = P^T F P with F's rows streamed (the `icobrdf fit` path). Direct: for every pair of "
             "points, f and the modes are evaluated and w w' f K_a K_b accumulated (per pair: the modes at the "
             "remitted point re-evaluated for each pair; cached: evaluated once per point). With one point per cell "
             "the direct sums equal the plain projection P = W B exactly, and G^-1 D G^-1 the least-squares one, so "
             "the differences below are rounding.\n\n",
             kDirectModel, o.threads, kDirectRepeats) +
         md_table(direct_vs_matrix_header(), rows);
}

}  // namespace

ReportSection run_baselines(const SectionOptions& o) {
  ReportSection s;
  s.title = "Baselines measured in the same run";
  if (o.levels.empty() || o.orders.empty()) throw ArgumentError("baselines: expected at least one level and one order");
  // Orders above kMaxBaselineOrder are left to the sweep's own table: B and G of five grids at order 64
  // would cost minutes.
  const int max_order = std::min(o.orders.back(), kMaxBaselineOrder);
  const std::vector<int> shown = shown_orders(o.orders, max_order);
  std::vector<int> cond_orders;
  for (int n : shown)
    if (n > 0) cond_orders.push_back(n);

  const std::vector<GridRun> runs = measure_matched_grids(o.levels, max_order, cond_orders);
  std::string md = intro(max_order) + gram_and_condition_tables(runs, shown);
  if (!o.report_dir.empty()) s.figures = draw_gram_figures(runs, max_order, o.report_dir);
  s.data["max_order"] = max_order;
  s.data["grids"] = runs_json(runs);
  md += largest_order_table(runs, max_order);
  nlohmann::json jneed;
  const std::string needed = cells_needed_table(runs, max_order, jneed);
  for (const auto& f : s.figures) md += "![" + f + "](" + f + ")\n";
  if (!s.figures.empty()) md += "\n";
  md += needed;
  s.data["cells_needed"] = jneed;
  nlohmann::json jd;
  md += direct_section(o, jd);
  s.data["direct_vs_matrix"] = jd;
  s.markdown = md;
  return s;
}

}  // namespace icobrdf::lab
