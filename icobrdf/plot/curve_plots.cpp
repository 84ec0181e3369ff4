#include "icobrdf/plot/curve_plots.hpp"

#include <cairo.h>
#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/mesh/tessellation.hpp"
#include "icobrdf/plot/slice_data.hpp"

namespace icobrdf::plot {
namespace {

constexpr double kDegPerRad = 180.0 / M_PI;  // degrees per radian
constexpr int kCurveSamples = 359;     // remitted directions per curve: every half degree
// Half a degree above the horizon: measured data at theta_r = 90 exactly can be far off (never measured).
constexpr double kCurveReach = (90.0 - 0.5) / kDegPerRad;
constexpr double kAlbedoStepDeg = 2.0;  // theta_i step of the albedo curve
constexpr double kAlbedoLastDeg = 88.0;  // last theta_i (grazing incidence itself is not drawn)

Eigen::Vector3d incident(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// The channel mean of values(w_i, w_r) at every row of wr for one incident direction.
Eigen::VectorXd mean_values(const PairFunction& values, const Eigen::Vector3d& wi, const RowMatrix3d& wr) {
  RowMatrix3d wis(wr.rows(), 3);
  wis.rowwise() = wi.transpose();
  const Eigen::MatrixXd v = values(wis, wr);
  if (v.rows() != wr.rows() || v.cols() < 1) throw ArgumentError("curve plot: the values have the wrong shape");
  return v.rowwise().mean();
}

void draw_polar_chart(Figure& fig, double cx, double cy, double R, const ValueScale& scale, const std::vector<Eigen::VectorXd>& curves,
                      const Eigen::VectorXd& t, const std::string& quantity) {
  cairo_t* cr = fig.context();
  cairo_save(cr);
  cairo_set_line_width(cr, 0.7);
  cairo_set_source_rgb(cr, 0.78, 0.78, 0.78);
  double last_label = -1e9;  // labels closer than 34 pixels are left out
  for (double v : scale.ticks()) {
    const double u = scale.unit(v);
    if (!(v > 0.0) || !(u > 0.0)) continue;
    cairo_new_path(cr);
    cairo_arc(cr, cx, cy, R * u, M_PI, 2 * M_PI);
    cairo_stroke(cr);
    if (R * u - last_label < 34.0) continue;
    last_label = R * u;
    fig.text(cx + R * u, cy + 13, format_number(v), 9.0, Align::Centre);
  }
  for (double a = -90.0; a <= 90.0; a += 30.0) {
    cairo_new_path(cr);
    cairo_move_to(cr, cx, cy);
    cairo_line_to(cr, cx - R * std::sin(a / kDegPerRad), cy - R * std::cos(a / kDegPerRad));
    cairo_stroke(cr);
    fig.text(cx - (R + 14) * std::sin(a / kDegPerRad), cy - (R + 14) * std::cos(a / kDegPerRad) + 4, format_number(std::fabs(a)) + "\u00b0", 10.0,
             Align::Centre);
  }
  cairo_restore(cr);
  fig.line(cx - R, cy, cx + R, cy, 1.0, {0.2, 0.2, 0.2});
  fig.text(cx - R / 2, cy + 30, "forward (mirror) side", 10.5, Align::Centre);
  fig.text(cx + R / 2, cy + 30, "backward (incident) side", 10.5, Align::Centre);
  fig.text(cx, cy + 48, fmt::format("radius: {} [1/sr]{}, angle: theta_r", quantity, scale.log ? " (log)" : ""), 11.0, Align::Centre);
  for (std::size_t k = 0; k < curves.size(); ++k)
    draw_polar_curve(fig, curves[k], t, cx, cy, R, scale, series_colour(static_cast<int>(k)), false);
}

}  // namespace

void draw_polar_curve(Figure& fig, const Eigen::MatrixXd& v, const Eigen::VectorXd& t, double cx, double cy, double R,
                      const ValueScale& scale, const Rgb& colour, bool negative) {
  cairo_t* cr = fig.context();
  cairo_save(cr);
  cairo_set_line_width(cr, 1.8);
  cairo_set_source_rgb(cr, colour[0], colour[1], colour[2]);
  cairo_new_path(cr);
  bool pen = false;
  for (Eigen::Index m = 0; m < t.size() && m < v.size(); ++m) {
    if (!std::isfinite(v(m)) || (v(m) < 0.0) != negative) {
      pen = false;
      continue;
    }
    const double r = R * std::fabs(scale.unit(v(m)));
    const double x = cx - r * std::sin(t(m)), y = cy - r * std::cos(t(m));
    if (pen) cairo_line_to(cr, x, y);
    else cairo_move_to(cr, x, y);
    pen = true;
  }
  cairo_stroke(cr);
  cairo_restore(cr);
}

CurveFigure plot_curves(const std::string& label, const PairFunction& values, const std::string& quantity, const CurveRequest& q,
                        const std::string& path) {
  if (q.theta_i.empty() || q.theta_i.size() > kMaxCurves)
    throw ArgumentError(fmt::format("curve plot: 1 to {} incidence angles, found {}", kMaxCurves, q.theta_i.size()));
  for (double t : q.theta_i)
    if (!(t >= 0.0 && t < M_PI / 2)) throw ArgumentError(fmt::format("curve plot: theta_i {} degrees outside [0, 90)", t * kDegPerRad));
  if (!values) throw ArgumentError("curve plot: no values to draw");
  const Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(kCurveSamples, -kCurveReach, kCurveReach);
  const RowMatrix3d plane = plane_of_incidence_directions(q.phi_i, t);
  std::vector<Eigen::VectorXd> curves;
  std::vector<Series> series;
  for (double ti : q.theta_i) {
    curves.push_back(mean_values(values, incident(ti, q.phi_i), plane));
    Series s;
    s.label = fmt::format("theta_i = {}\u00b0", format_number(std::round(ti * kDegPerRad * 10) / 10));
    s.marker = Marker::None;
    for (Eigen::Index m = 0; m < t.size(); ++m) {
      s.x.push_back(t(m) * kDegPerRad);
      s.y.push_back(curves.back()(m));
    }
    series.push_back(std::move(s));
  }
  std::vector<Eigen::MatrixXd> as_matrices(curves.begin(), curves.end());
  std::vector<const Eigen::MatrixXd*> all;
  for (const auto& m : as_matrices) all.push_back(&m);
  ValueScale scale = value_scale(all, q.log);
  scale.is_signed = false;  // the polar radius: negative values (ringing of a fit) are left out

  CurveFigure out;
  out.width = 1180;
  out.height = 520;
  Figure fig(out.width, out.height);
  fig.title("In-plane curves of " + (label.size() > 80 ? label.substr(0, 77) + "..." : label), 17.0);
  fig.text(out.width / 2.0, 50,
           fmt::format("{} in the plane of incidence (phi_i = {}\u00b0){}; theta_r > 0 on the forward side", quantity,
                       format_number(std::round(q.phi_i * kDegPerRad * 100) / 100), q.log ? ", log scale" : ""),
           12.5, Align::Centre);
  ChartOptions co;
  co.x_label = "signed theta_r [deg] (forward side > 0)";
  co.y_label = quantity + " [1/sr]";
  co.log_y = q.log;
  co.x_min = -90;
  co.x_max = 90;
  if (q.log) co.y_min = scale.bottom, co.y_max = scale.top;
  co.legend = LegendPlace::Right;
  out.cartesian = draw_line_chart(fig, {0, 60, 640, out.height - 60}, series, co);
  out.polar_radius = 220;
  out.polar_cx = 640 + 270;
  out.polar_cy = 60 + 30 + out.polar_radius;
  out.scale = scale;
  draw_polar_chart(fig, out.polar_cx, out.polar_cy, out.polar_radius, scale, curves, t, quantity);
  fig.save_png(path);
  return out;
}

AlbedoFigure plot_albedo(const std::string& label, const PairFunction& values, int channels, const std::vector<std::string>& names,
                         double phi_i, const std::string& path) {
  if (!values) throw ArgumentError("albedo plot: no values to integrate");
  static const Grid g = build_equal_area_grid(kCurveAlbedoLevel);
  const Eigen::VectorXd wcos = g.solid_angles.cwiseProduct(g.directions.col(2));
  AlbedoFigure out;
  out.albedo.assign(static_cast<std::size_t>(channels), {});
  // Every theta_i's pairs in one batch (one parallel region of the source's evaluation, not one per angle).
  for (double d = 0.0; d <= kAlbedoLastDeg + 1e-9; d += kAlbedoStepDeg) out.theta_i_deg.push_back(d);
  const Eigen::Index cells = g.cells(), angles = static_cast<Eigen::Index>(out.theta_i_deg.size());
  RowMatrix3d wis(cells * angles, 3), wrs(cells * angles, 3);
  for (Eigen::Index t = 0; t < angles; ++t) {
    wis.middleRows(t * cells, cells).rowwise() = incident(out.theta_i_deg[static_cast<std::size_t>(t)] / kDegPerRad, phi_i).transpose();
    wrs.middleRows(t * cells, cells) = g.directions;
  }
  const Eigen::MatrixXd v = values(wis, wrs);
  if (v.rows() != wis.rows() || v.cols() != channels)
    throw ArgumentError(fmt::format("albedo plot: {} x {} values expected, found {} x {}", wis.rows(), channels, v.rows(), v.cols()));
  for (Eigen::Index t = 0; t < angles; ++t)
    for (int c = 0; c < channels; ++c) {
      double a = 0.0;  // cells without a value (a table's empty bins) are left out
      for (Eigen::Index k = 0; k < cells; ++k)
        if (std::isfinite(v(t * cells + k, c))) a += v(t * cells + k, c) * wcos(k);
      out.albedo[static_cast<std::size_t>(c)].push_back(a);
    }
  std::vector<Series> series;
  const Rgb rgb[3] = {{0.85, 0.15, 0.1}, {0.1, 0.6, 0.15}, {0.15, 0.3, 0.9}};
  for (int c = 0; c < channels; ++c) {
    Series s;
    s.label = c < static_cast<int>(names.size()) ? names[c] : channels == 1 ? "albedo" : fmt::format("channel {}", c);
    if (channels == 3) s.colour = rgb[c];
    s.marker = Marker::None;
    s.x = out.theta_i_deg;
    s.y = out.albedo[static_cast<std::size_t>(c)];
    series.push_back(std::move(s));
  }
  Series passive{"a = 1 (passive limit)", {0.0, 90.0}, {1.0, 1.0}, {0.4, 0.4, 0.4}, Marker::None, true, true, 1.0};
  series.push_back(passive);
  double top = 0.0;
  for (const auto& a : out.albedo)
    for (double x : a) top = std::max(top, x);
  ChartOptions co;
  co.title = "Directional albedo of " + (label.size() > 70 ? label.substr(0, 67) + "..." : label);
  co.x_label = "theta_i [deg]";
  co.y_label = "a(theta_i) = \u222b f cos(theta_r) d\u03c9_r";
  co.x_min = 0;
  co.x_max = 90;
  co.y_min = 0;
  co.y_max = std::max(1.1, top * 1.05);
  co.width = 760;
  co.height = 460;
  co.legend = LegendPlace::BottomLeft;
  co.note = fmt::format("phi_i = {}\u00b0; midpoint rule over {} equal-area cells of the hemisphere (level {})",
                        format_number(std::round(phi_i * kDegPerRad * 100) / 100), g.cells(), kCurveAlbedoLevel);
  out.frame = draw_line_chart(series, co, path);
  out.width = co.width;
  out.height = co.height;
  return out;
}

}  // namespace icobrdf::plot
