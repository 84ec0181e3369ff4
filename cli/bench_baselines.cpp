// Report section "baselines" of `icobrdf bench sweep`, also runnable alone:
//   icobrdf bench baselines [--levels 1..5] [--orders 0..32] [--quick] [--json] [--report DIR]
//
// 1. How many cells each hemisphere grid needs to resolve an order: for the equal-area grid at every level
//    (cell averages with its degree-9 cubature, and centre sampling), the geodesic grid of the same level
//    (exact cell weights, degree-9 cubature), a latitude-longitude grid with about the same cell count
//    (n_theta x 4 n_theta cells, 5 x 5 Gauss points per cell: degree 9 as well) and the polar-Gauss product
//    rule with about the same node count (r rings x 4r azimuths, exact to order 2r - 1): the Gram error
//    max|G - I| and the condition number of G per order, the largest order each supports at the tolerances
//    0.1, 1e-2, 1e-3, and the cells each needs for orders 4, 8, 12, 16 (smallest built size meeting the
//    tolerance, and the log-log interpolation between the two built sizes around it; for the polar-Gauss
//    rule the smallest ring count found by search with 2n + 1 azimuths).
// 2. Direct quadrature without matrices (core/direct_projection.hpp: per cubature pair, the modes are
//    evaluated and the coefficients accumulated) against the matrix path (B sampled once, C = P^T F P by
//    streaming), for GGX alpha 0.2 on centre-sampled equal-area grids: times, speed ratio, agreement.
//    With one point per cell both compute the same sums, so they must agree to rounding.
#include <fmt/core.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <map>

#include "cli/bench_section_support.hpp"
#include "core/direct_projection.hpp"
#include "core/discrete_basis.hpp"
#include "core/hemisphere_basis.hpp"
#include "core/model_spec.hpp"
#include "core/projection.hpp"
#include "core/reference_grids.hpp"
#include "core/streaming_projection.hpp"
#include "mesh/tessellation.hpp"
#include "plot/line_chart.hpp"

namespace icobrdf::cli {
namespace {

using namespace section;

// Gram-error tolerances of the "largest order" and "cells needed" tables: the library's default (10%) and
// two stricter ones.
constexpr double kTolerances[] = {1e-1, 1e-2, 1e-3};
// Orders whose cell counts are reported.
constexpr int kNeededOrders[] = {4, 8, 12, 16};
// Gauss points per direction in a lat-long cell: degree 2*5-1 = 9 in cos(theta) and phi, as the degree-9
// rule of the icosahedral cells.
constexpr int kLatLongPoints = 5;
// Floor of the log-scale figures: Gram errors of exact rules are rounding, shown at machine epsilon.
constexpr double kEps = std::numeric_limits<double>::epsilon();
// Timed repetitions of each path in the direct-vs-matrix comparison (the best is reported; the first run
// also pays for thread start-up and first touch of the buffers).
constexpr int kRepeats = 2;
// Largest order measured on the baseline grids (the sweep may ask for more).
constexpr int kMaxBaselineOrder = 32;
// The model of the direct-vs-matrix comparison.
constexpr const char* kDirectModel = "ggx:alpha=0.2";

struct GridRun {
  std::string kind;   // equal-area, equal-area-centre, geodesic, lat-long, polar-gauss
  std::string size;   // "level 3" or "rings x azimuths"
  int level = 0;      // tessellation level whose cell count it matches
  int cells = 0;
  int rings = 0, azimuths = 0;  // lat-long bands x sectors, polar-gauss rings x azimuths (0 for the others)
  Eigen::Index points = 0;
  double grid_seconds = 0.0, basis_seconds = 0.0;
  std::vector<double> gram;           // max|G - I| per order 0..max order
  std::map<int, double> condition;    // lambda_max / lambda_min of G, at the reported orders
  std::vector<int> largest;           // largest supported order per tolerance of kTolerances
};

// max|G - I| of the leading block of order n, for n = 0..order.
std::vector<double> gram_errors(const DiscreteBasis& b) {
  std::vector<double> e;
  for (int n = 0; n <= b.order; ++n) {
    const int m = hemisphere_basis_count(n);
    e.push_back((b.G.topLeftCorner(m, m) - Eigen::MatrixXd::Identity(m, m)).cwiseAbs().maxCoeff());
  }
  return e;
}

double condition_of_block(const DiscreteBasis& b, int n) {
  const int m = hemisphere_basis_count(n);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(b.G.topLeftCorner(m, m), Eigen::EigenvaluesOnly);
  const double lo = eig.eigenvalues().minCoeff(), hi = eig.eigenvalues().maxCoeff();
  return lo > 0.0 ? hi / lo : std::numeric_limits<double>::infinity();
}

GridRun measure_grid(const std::string& kind, const std::string& size, int level, const std::function<Grid()>& build,
                     int order, const std::vector<int>& condition_orders) {
  GridRun r;
  r.kind = kind;
  r.size = size;
  r.level = level;
  Grid g;
  r.grid_seconds = seconds_of([&] { g = build(); });
  DiscreteBasis b;
  r.basis_seconds = seconds_of([&] { b = build_discrete_basis(g, order); });
  r.cells = g.cells();
  r.points = g.cubature_points.rows();
  r.gram = gram_errors(b);
  for (int n : condition_orders) r.condition[n] = condition_of_block(b, n);
  for (double tol : kTolerances) r.largest.push_back(largest_supported_order(b, tol));
  return r;
}

// Polar-Gauss rule with 2n + 1 azimuths: the smallest ring count whose Gram error at order n is <= tol
// (search upward; exactness predicts rings = ceil((n + 1)/2)). Returns {rings, cells, gram error}.
struct PolarSearch {
  int rings = 0, cells = 0;
  double gram = 0.0, gram_one_ring_less = std::numeric_limits<double>::quiet_NaN();
};
PolarSearch polar_gauss_search(int n, double tol) {
  PolarSearch s;
  const int n_phi = 2 * n + 1;
  double previous = std::numeric_limits<double>::quiet_NaN();
  for (int rings = 1; rings <= n + 2; ++rings) {
    const auto b = build_discrete_basis(build_polar_gauss_grid(rings, n_phi), n);
    if (b.gram_error <= tol) {
      s.rings = rings;
      s.cells = rings * n_phi;
      s.gram = b.gram_error;
      s.gram_one_ring_less = previous;
      return s;
    }
    previous = b.gram_error;
  }
  return s;  // rings = 0: not found (cannot happen for an exact rule; reported as such)
}

// Cells for Gram error `tol` at order n from a family of sizes (ascending cells): the first size meeting it,
// and the log-log interpolation between it and the size before (the Gram error of cell averages falls as a
// power of the cell size). NaN interpolation when the first size already meets it or none does.
struct CellsNeeded {
  int smallest_built = -1;  // -1: none of the built sizes meets the tolerance
  double interpolated = std::numeric_limits<double>::quiet_NaN();
};
CellsNeeded cells_needed(const std::vector<const GridRun*>& family, int n, double tol) {
  CellsNeeded c;
  for (size_t k = 0; k < family.size(); ++k) {
    const double e = family[k]->gram[static_cast<size_t>(n)];
    if (e > tol) continue;
    c.smallest_built = family[k]->cells;
    if (k > 0) {
      const double e0 = family[k - 1]->gram[static_cast<size_t>(n)];
      const double c0 = family[k - 1]->cells, c1 = family[k]->cells;
      if (e0 > tol && e > 0.0)
        c.interpolated = std::exp(std::log(c0) + (std::log(tol) - std::log(e0)) * (std::log(c1) - std::log(c0)) / (std::log(e) - std::log(e0)));
    }
    break;
  }
  return c;
}

struct DirectCase {
  int level, order;
};

nlohmann::json direct_vs_matrix(const DirectCase& dc, std::vector<std::string>& row) {
  const auto model = parse_model(kDirectModel);
  const Grid g = build_fitting_grid(dc.level, "equal-area", true);  // one point per cell (centre sampling)
  // Matrix path as `icobrdf fit` runs it: B and P once, then C = P^T F P with F's rows streamed.
  DiscreteBasis basis;
  ProjectionOperator ls, plain;
  std::vector<Eigen::MatrixXd> c_ls, c_plain, d_pair, d_cached;
  const auto best = [](auto&& f) {
    double t = 1e300;
    for (int k = 0; k < kRepeats; ++k) t = std::min(t, seconds_of(f));
    return t;
  };
  const double t_operators = best([&] {
    basis = build_discrete_basis(g, dc.order);
    ls = make_projection(basis);
  });
  const double t_stream = best([&] { c_ls = streaming_projection(*model, g, ls, false); });
  plain = make_projection(basis, ProjectionOperator::Kind::Plain);
  c_plain = streaming_projection(*model, g, plain, false);
  const double t_pair = best([&] { d_pair = direct_projection(*model, g, dc.order, false, DirectModes::PerPair); });
  const double t_cached = best([&] { d_cached = direct_projection(*model, g, dc.order, false, DirectModes::Cached); });
  // Direct sums are the plain projection; the least-squares one is G^-1 D G^-1 (core/direct_projection.hpp).
  const Eigen::MatrixXd gi = basis.G.inverse();
  const Eigen::MatrixXd d_ls = gi * d_pair[0] * gi;
  const double scale = c_plain[0].cwiseAbs().maxCoeff();
  const double agree_plain = (d_pair[0] - c_plain[0]).cwiseAbs().maxCoeff() / scale;
  const double agree_cached = (d_cached[0] - c_plain[0]).cwiseAbs().maxCoeff() / scale;
  const double agree_ls = (d_ls - c_ls[0]).cwiseAbs().maxCoeff() / c_ls[0].cwiseAbs().maxCoeff();
  const double t_matrix = t_operators + t_stream;
  const long long pairs = static_cast<long long>(g.cells()) * g.cells();
  row = {std::to_string(dc.level),     std::to_string(g.cells()),        std::to_string(dc.order),
         std::to_string(basis.modes()), fixed(t_matrix, 3),               fixed(t_pair, 3),
         fixed(t_cached, 3),            fixed(t_pair / t_matrix, 1) + "x", fixed(t_cached / t_matrix, 1) + "x",
         sci(agree_plain),              sci(agree_ls)};
  return {{"level", dc.level},
          {"cells", g.cells()},
          {"order", dc.order},
          {"modes", basis.modes()},
          {"pairs", pairs},
          {"model", kDirectModel},
          {"matrix_operator_seconds", t_operators},
          {"matrix_projection_seconds", t_stream},
          {"matrix_seconds", t_matrix},
          {"direct_per_pair_seconds", t_pair},
          {"direct_cached_seconds", t_cached},
          {"per_pair_over_matrix", t_pair / t_matrix},
          {"cached_over_matrix", t_cached / t_matrix},
          {"agreement_plain", agree_plain},
          {"agreement_cached_plain", agree_cached},
          {"agreement_least_squares", agree_ls},
          {"gram_error", basis.gram_error},
          {"condition", basis.condition}};
}

ReportSection run_baselines(const SectionOptions& o) {
  ReportSection s;
  s.title = "Baselines measured in the same run";
  if (o.levels.empty() || o.orders.empty()) throw ArgumentError("baselines: expected at least one level and one order");
  // Orders above kMaxBaselineOrder are left to the sweep's own table: B and G of five grids at order 64
  // would cost minutes.
  const int max_order = std::min(o.orders.back(), kMaxBaselineOrder);
  std::vector<int> shown;  // orders in the tables: the requested ones that are 2, 4, 8, 12, ... (all when few)
  for (int n : o.orders)
    if (n <= max_order && (o.orders.size() <= 8 || n == 2 || (n % 4 == 0 && n > 0))) shown.push_back(n);
  std::vector<int> cond_orders;
  for (int n : shown)
    if (n > 0) cond_orders.push_back(n);

  // 1. Grids of matched sizes.
  std::vector<GridRun> runs;
  for (int level : o.levels) {
    Grid ea;
    const double t_ea = seconds_of([&] { ea = build_equal_area_grid(level); });
    {
      GridRun r = measure_grid("equal-area", "level " + std::to_string(level), level, [&] { return ea; }, max_order, cond_orders);
      r.grid_seconds = t_ea;
      runs.push_back(r);
    }
    runs.push_back(measure_grid("equal-area-centre", "level " + std::to_string(level), level,
                                [&] { return with_centre_cubature(ea); }, max_order, cond_orders));
    runs.push_back(measure_grid("geodesic", "level " + std::to_string(level), level, [&] { return build_geodesic_grid(level); },
                                max_order, cond_orders));
    const int k = std::max(1, static_cast<int>(std::lround(std::sqrt(ea.cells() / 4.0))));
    runs.push_back(measure_grid("lat-long", fmt::format("{} x {}", k, 4 * k), level,
                                [&] { return build_lat_long_grid(k, 4 * k, kLatLongPoints); }, max_order, cond_orders));
    runs.back().rings = k;
    runs.back().azimuths = 4 * k;
    runs.push_back(measure_grid("polar-gauss", fmt::format("{} x {}", k, 4 * k), level,
                                [&] { return build_polar_gauss_grid(k, 4 * k); }, max_order, cond_orders));
    runs.back().rings = k;
    runs.back().azimuths = 4 * k;
  }
  const std::vector<std::string> kinds = {"equal-area", "equal-area-centre", "geodesic", "lat-long", "polar-gauss"};

  std::string md;
  md += fmt::format(
      "Every grid samples the hemisphere basis K up to order {} (B, cells x modes) and forms G = B^T W B; "
      "G = I for the continuous basis, so max|G - I| says how faithfully the grid represents each order. "
      "Equal-area and geodesic: the icosahedral cells of the level with their degree-{} cubature (cell averages), "
      "equal-area-centre: the same cells sampled at their centres (what `icobrdf fit` uses); lat-long: n x 4n "
      "cells uniform in theta and phi with {} x {} Gauss points each; polar-gauss: r Gauss-Legendre rings in "
      "rho^2 x 4r azimuths (one point per node, exact to order 2r - 1). Lat-long and polar-gauss are matched "
      "to the level's cell count.\n\n",
      max_order, kDefaultCubatureDegree, kLatLongPoints, kLatLongPoints);

  {  // Gram error and condition tables
    std::vector<std::string> h = {"grid", "size", "cells", "points"};
    for (int n : shown) h.push_back("N=" + std::to_string(n));
    std::vector<std::vector<std::string>> gram_rows, cond_rows;
    for (const auto& kind : kinds)
      for (const auto& r : runs) {
        if (r.kind != kind) continue;
        std::vector<std::string> a = {r.kind, r.size, std::to_string(r.cells), std::to_string(r.points)}, c = a;
        for (int n : shown) a.push_back(sci(r.gram[static_cast<size_t>(n)], 1));
        for (int n : shown) c.push_back(n > 0 ? sci(r.condition.at(n), 2) : "1");
        gram_rows.push_back(a);
        cond_rows.push_back(c);
      }
    md += "### Gram error max|G - I| by order\n\n" + md_table(h, gram_rows);
    md += "### Condition number of G by order\n\n" + md_table(h, cond_rows);
  }

  nlohmann::json jruns = nlohmann::json::array();
  for (const auto& r : runs) {
    nlohmann::json cond = nlohmann::json::object(), largest = nlohmann::json::object();
    for (const auto& [n, v] : r.condition) cond[std::to_string(n)] = num(v);
    for (size_t t = 0; t < std::size(kTolerances); ++t) largest[sci(kTolerances[t], 0)] = r.largest[t];
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
  if (!o.report_dir.empty()) {  // figure: Gram error vs cells, one chart per order (log-log)
    for (int n : kNeededOrders) {
      if (n > max_order) continue;
      std::vector<plot::Series> series;
      for (const auto& kind : kinds) {
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
      plot::draw_line_chart(series, co, (o.report_dir / file).string());
      s.figures.push_back(file);
    }
  }
  s.data["max_order"] = max_order;
  s.data["grids"] = jruns;

  {  // largest supported order per tolerance
    std::vector<std::string> h = {"grid", "size", "cells"};
    for (double t : kTolerances) h.push_back("tol " + sci(t, 0));
    std::vector<std::vector<std::string>> rows;
    for (const auto& kind : kinds)
      for (const auto& r : runs) {
        if (r.kind != kind) continue;
        std::vector<std::string> a = {r.kind, r.size, std::to_string(r.cells)};
        for (size_t t = 0; t < std::size(kTolerances); ++t)
          a.push_back(r.largest[t] == max_order ? ">= " + std::to_string(max_order) : std::to_string(r.largest[t]));
        rows.push_back(a);
      }
    md += fmt::format("### Largest order supported at a Gram tolerance (orders <= {} measured)\n\n", max_order) + md_table(h, rows);
  }

  {  // cells needed
    std::vector<std::string> h = {"grid", "tolerance"};
    std::vector<int> orders;
    for (int n : kNeededOrders)
      if (n <= max_order) orders.push_back(n);
    for (int n : orders) h.push_back("N=" + std::to_string(n));
    std::vector<std::vector<std::string>> rows;
    nlohmann::json jneed = nlohmann::json::array();
    for (const auto& kind : kinds) {
      std::vector<const GridRun*> family;
      for (const auto& r : runs)
        if (r.kind == kind) family.push_back(&r);
      std::sort(family.begin(), family.end(), [](const GridRun* a, const GridRun* b) { return a->cells < b->cells; });
      for (double tol : kTolerances) {
        std::vector<std::string> a = {kind, sci(tol, 0)};
        for (int n : orders) {
          if (kind == "polar-gauss") {
            const PolarSearch ps = polar_gauss_search(n, tol);
            a.push_back(ps.rings > 0 ? fmt::format("{} ({} x {})", ps.cells, ps.rings, 2 * n + 1) : "not found");
            jneed.push_back({{"kind", kind}, {"tolerance", tol}, {"order", n}, {"cells", ps.cells}, {"rings", ps.rings},
                             {"azimuths", 2 * n + 1}, {"gram_error", ps.gram}, {"gram_error_one_ring_less", num(ps.gram_one_ring_less)},
                             {"exactness_rings", (n + 2) / 2}});
            continue;
          }
          const CellsNeeded c = cells_needed(family, n, tol);
          std::string cell = c.smallest_built < 0 ? "> " + std::to_string(family.back()->cells) : std::to_string(c.smallest_built);
          if (std::isfinite(c.interpolated)) cell += fmt::format(" (~{:.0f})", c.interpolated);
          a.push_back(cell);
          jneed.push_back({{"kind", kind}, {"tolerance", tol}, {"order", n}, {"smallest_built_cells", c.smallest_built},
                           {"interpolated_cells", num(c.interpolated)}});
        }
        rows.push_back(a);
      }
    }
    for (const auto& f : s.figures) md += "![" + f + "](" + f + ")\n";
    if (!s.figures.empty()) md += "\n";
    md += "### Cells needed for a Gram error\n\n"
          "Smallest built size meeting the tolerance, with the log-log interpolation between it and the size "
          "before in parentheses (the Gram error of cell averages falls as a power of the cell size). "
          "Polar-gauss: the smallest ring count r found by search with 2N + 1 azimuths (exactness predicts "
          "r = floor(N/2) + 1), cells = r (2N + 1).\n\n" +
          md_table(h, rows);
    s.data["cells_needed"] = jneed;
  }

  {  // direct quadrature vs matrices
    std::vector<DirectCase> cases;
    if (o.quick)
      cases = {{2, 4}, {3, 6}};
    else
      cases = {{3, 6}, {4, 8}};
    std::vector<std::vector<std::string>> rows;
    nlohmann::json jd = nlohmann::json::array();
    for (const auto& dc : cases) {
      std::vector<std::string> row;
      jd.push_back(direct_vs_matrix(dc, row));
      rows.push_back(row);
    }
    s.data["direct_vs_matrix"] = jd;
    md += fmt::format(
        "### Direct quadrature without matrices vs the matrix path\n\n"
        "Model `{}`, equal-area cells sampled at their centres, {} thread(s), best of {} runs. Matrix: B, G and P = W B G^-1 built "
        "once, then C = P^T F P with F's rows streamed (the `icobrdf fit` path). Direct: for every pair of "
        "points, f and the modes are evaluated and w w' f K_a K_b accumulated (per pair: the modes at the "
        "remitted point re-evaluated for each pair; cached: evaluated once per point). With one point per cell "
        "the direct sums equal the plain projection P = W B exactly, and G^-1 D G^-1 the least-squares one, so "
        "the differences below are rounding.\n\n",
        kDirectModel, o.threads, kRepeats);
    md += md_table({"level", "cells", "order", "modes", "matrix [s]", "direct per pair [s]", "direct cached [s]", "per pair / matrix",
                    "cached / matrix", "max diff plain (rel)", "max diff least squares (rel)"},
                   rows);
  }
  s.markdown = md;
  return s;
}

const ReportSectionRegistrar kSection("baselines", run_baselines);
const BenchRegistrar kCommand("baselines", [](CLI::App& bench) {
  add_section_subcommand(bench, "baselines",
                         "Baseline grids (geodesic, lat-long, polar Gauss) and direct quadrature against the equal-area matrix path",
                         {"1..5", "0..32", "1..3", "0..12", 6, kMaxBaselineOrder}, run_baselines);
});

}  // namespace
}  // namespace icobrdf::cli
