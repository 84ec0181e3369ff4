#include "icobrdf/plot/line_chart.hpp"

#include <cairo.h>
#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/plot/figure.hpp"

namespace icobrdf::plot {
namespace {

constexpr double kTitleSize = 15.0, kLabelSize = 13.0, kTickSize = 11.5, kLegendSize = 12.0, kNoteSize = 11.0;
constexpr double kMarkerRadius = 3.6;
// Relative slack when listing ticks, so that an end of the range equal to a tick up to rounding keeps it.
constexpr double kTickSlack = 1e-9;
// Values closer than this (relative) are one value: sums of a few hundred rounded terms differ by ~1e-14.
constexpr double kFlatSpread = 1e-9;
// Tick indices are counted in doubles, exact only below 2^53; a chart has a few dozen ticks at most.
constexpr double kMaxTickIndex = 1e6;

const Rgb kAxisColour{0.15, 0.15, 0.15};
const Rgb kGridColour{0.88, 0.88, 0.88};

bool drawable(double v, bool log) { return std::isfinite(v) && (!log || v > 0.0); }

double axis_value(double v, bool log) { return log ? std::log10(v) : v; }

double text_width(cairo_t* cr, const std::string& s, double size) {
  cairo_save(cr);
  cairo_select_font_face(cr, kFontFace, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
  cairo_text_extents_t e;
  cairo_text_extents(cr, s.c_str(), &e);
  cairo_restore(cr);
  return e.x_advance;
}

double nice_step(double raw) {
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * mag >= raw * (1.0 - kTickSlack)) return m * mag;
  return 10.0 * mag;
}

double linear_step(double lo, double hi, int target, bool integers) {
  double step = nice_step((hi - lo) / std::max(1, target));
  if (integers) step = std::max(1.0, std::round(step));
  return step;
}

// Automatic range of one axis from the drawable values; fixed ends kept.
void axis_range(const std::vector<double>& values, bool log, bool integers, double fixed_lo, double fixed_hi, double& lo,
                double& hi) {
  double mn = std::numeric_limits<double>::infinity(), mx = -mn;
  for (double v : values)
    if (drawable(v, log)) {
      mn = std::min(mn, v);
      mx = std::max(mx, v);
    }
  if (!std::isnan(fixed_lo)) mn = std::min(mn, fixed_lo), mx = std::max(mx, fixed_lo);
  if (!std::isnan(fixed_hi)) mn = std::min(mn, fixed_hi), mx = std::max(mx, fixed_hi);
  if (mn > mx) mn = mx = log ? 1.0 : 0.0;  // no data
  if (log) {
    lo = std::pow(10.0, std::floor(std::log10(mn) + kTickSlack));
    hi = std::pow(10.0, std::ceil(std::log10(mx) - kTickSlack));
    if (!(hi > lo)) lo /= 10.0, hi *= 10.0;
  } else {
    // A spread within rounding of the values is no spread: ticks 1e-18 apart on values near 0.16 (the
    // in-plane curve of a Lambertian spectrum at normal incidence, equal to 1 ulp) counted k += 1 beyond 2^53,
    // where k + 1 == k, and filled memory. Such data are drawn as flat, around their value.
    if (!(mx - mn > kFlatSpread * std::max(std::fabs(mn), std::fabs(mx)))) {
      const double c = (mn + mx) / 2, half = c != 0.0 ? std::fabs(c) : 1.0;
      mn = c - half, mx = c + half;
    }
    const double step = linear_step(mn, mx, 6, integers);
    lo = std::floor(mn / step + kTickSlack) * step;
    hi = std::ceil(mx / step - kTickSlack) * step;
  }
  if (!std::isnan(fixed_lo)) lo = fixed_lo;
  if (!std::isnan(fixed_hi)) hi = fixed_hi;
  if (!(hi > lo)) throw ArgumentError(fmt::format("chart axis range [{}, {}]: expected min < max", lo, hi));
  if (log && !(lo > 0.0)) throw ArgumentError(fmt::format("chart log axis range [{}, {}]: expected min > 0", lo, hi));
}

std::string tick_label(double v, bool log, double step) {
  if (log) {
    const double e = std::round(std::log10(v));
    if (std::fabs(v / std::pow(10.0, e) - 1.0) < 1e-9) {  // a power of ten
      if (e >= -3 && e <= 3) return e < 0 ? fmt::format("{:.{}f}", v, static_cast<int>(-e)) : fmt::format("{:.0f}", v);
      return fmt::format("1e{}", static_cast<int>(e));
    }
    return format_number(v);
  }
  if (std::fabs(v) < step * kTickSlack) return "0";
  if (step >= 1.0 && std::fabs(v) < 1e6) return fmt::format("{:.0f}", v);
  return format_number(v);
}

void set_colour(cairo_t* cr, const Rgb& c) { cairo_set_source_rgb(cr, c[0], c[1], c[2]); }

Marker marker_of(const Series& s, int index) {
  if (s.marker != Marker::Auto) return s.marker;
  static const Marker cycle[] = {Marker::Circle, Marker::Square, Marker::Triangle, Marker::Diamond, Marker::Cross};
  return cycle[index % 5];
}

Rgb colour_of(const Series& s, int index) {
  return s.colour[0] < 0 || s.colour[1] < 0 || s.colour[2] < 0 ? series_colour(index) : s.colour;
}

void draw_marker(cairo_t* cr, Marker m, double x, double y, const Rgb& c) {
  const double r = kMarkerRadius;
  set_colour(cr, c);
  cairo_new_path(cr);
  switch (m) {
    case Marker::None:
    case Marker::Auto:
      return;
    case Marker::Circle:
      cairo_arc(cr, x, y, r, 0.0, 2 * M_PI);
      cairo_fill(cr);
      return;
    case Marker::Square:
      cairo_rectangle(cr, x - r, y - r, 2 * r, 2 * r);
      cairo_fill(cr);
      return;
    case Marker::Triangle:
      cairo_move_to(cr, x, y - 1.25 * r);
      cairo_line_to(cr, x + 1.15 * r, y + 0.85 * r);
      cairo_line_to(cr, x - 1.15 * r, y + 0.85 * r);
      cairo_close_path(cr);
      cairo_fill(cr);
      return;
    case Marker::Diamond:
      cairo_move_to(cr, x, y - 1.3 * r);
      cairo_line_to(cr, x + 1.3 * r, y);
      cairo_line_to(cr, x, y + 1.3 * r);
      cairo_line_to(cr, x - 1.3 * r, y);
      cairo_close_path(cr);
      cairo_fill(cr);
      return;
    case Marker::Cross:
      cairo_set_line_width(cr, 2.2);
      cairo_move_to(cr, x - r, y - r);
      cairo_line_to(cr, x + r, y + r);
      cairo_move_to(cr, x - r, y + r);
      cairo_line_to(cr, x + r, y - r);
      cairo_stroke(cr);
      return;
  }
}

struct Layout {
  ChartFrame frame;
  std::vector<double> x_ticks, y_ticks;
  double x_step = 1, y_step = 1;
  double legend_x = 0, legend_w = 0;
};

Layout layout(Figure& fig, const ChartBox& box, const std::vector<Series>& series, const ChartOptions& o) {
  std::vector<double> xs, ys;
  for (const auto& s : series) {
    if (s.x.size() != s.y.size())
      throw ArgumentError(fmt::format("chart series '{}': {} x values and {} y values, expected as many", s.label, s.x.size(), s.y.size()));
    for (std::size_t k = 0; k < s.x.size(); ++k)
      if (drawable(s.x[k], o.log_x) && drawable(s.y[k], o.log_y)) xs.push_back(s.x[k]), ys.push_back(s.y[k]);
  }
  if (box.width < 120 || box.height < 100)
    throw ArgumentError(fmt::format("chart box {}x{}: expected at least 120x100 pixels", box.width, box.height));
  Layout L;
  ChartFrame& f = L.frame;
  f.log_x = o.log_x;
  f.log_y = o.log_y;
  axis_range(xs, o.log_x, o.integer_x, o.x_min, o.x_max, f.x0, f.x1);
  axis_range(ys, o.log_y, false, o.y_min, o.y_max, f.y0, f.y1);
  L.x_ticks = axis_ticks(f.x0, f.x1, o.log_x, 7, o.integer_x);
  L.y_ticks = axis_ticks(f.y0, f.y1, o.log_y, 6, false);
  if (!o.log_x) L.x_step = linear_step(f.x0, f.x1, 7, o.integer_x);
  if (!o.log_y) L.y_step = linear_step(f.y0, f.y1, 6, false);
  cairo_t* cr = fig.context();
  double tick_w = 0.0;
  for (double t : L.y_ticks) tick_w = std::max(tick_w, text_width(cr, tick_label(t, o.log_y, L.y_step), kTickSize));
  double legend_w = 0.0;
  if (o.legend == LegendPlace::Right || o.legend == LegendPlace::TopRight || o.legend == LegendPlace::BottomLeft)
    for (const auto& s : series)
      if (!s.label.empty()) legend_w = std::max(legend_w, text_width(cr, s.label, kLegendSize) + 38.0);
  const double top_margin = (o.title.empty() ? 10.0 : 10.0 + kTitleSize + 12.0);
  const double left_margin = 10.0 + (o.y_label.empty() ? 0.0 : kLabelSize + 8.0) + tick_w + 8.0;
  const double bottom_margin = 8.0 + kTickSize + 8.0 + (o.x_label.empty() ? 0.0 : kLabelSize + 8.0) + (o.note.empty() ? 0.0 : kNoteSize + 6.0);
  const double right_margin = o.legend == LegendPlace::Right && legend_w > 0 ? legend_w + 24.0 : 18.0;
  f.left = box.x + left_margin;
  f.top = box.y + top_margin;
  f.right = box.x + box.width - right_margin;
  f.bottom = box.y + box.height - bottom_margin;
  if (f.right - f.left < 40 || f.bottom - f.top < 40)
    throw ArgumentError(fmt::format("chart box {}x{}: too small for its labels and legend", box.width, box.height));
  L.legend_w = legend_w;
  L.legend_x = f.right + 14.0;
  return L;
}

void draw_legend(Figure& fig, const Layout& L, const std::vector<Series>& series, const ChartOptions& o) {
  if (o.legend == LegendPlace::None || L.legend_w <= 0) return;
  cairo_t* cr = fig.context();
  const ChartFrame& f = L.frame;
  int entries = 0;
  for (const auto& s : series) entries += !s.label.empty();
  const double row = kLegendSize + 7.0;
  const double h = entries * row + 8.0;
  double x = L.legend_x, y = f.top + 4.0;
  if (o.legend == LegendPlace::TopRight) x = f.right - L.legend_w - 8.0, y = f.top + 8.0;
  if (o.legend == LegendPlace::BottomLeft) x = f.left + 8.0, y = f.bottom - h - 8.0;
  cairo_save(cr);
  if (o.legend != LegendPlace::Right) {
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_rectangle(cr, x, y, L.legend_w, h);
    cairo_fill_preserve(cr);
    set_colour(cr, {0.7, 0.7, 0.7});
    cairo_set_line_width(cr, 1.0);
    cairo_stroke(cr);
  }
  int k = 0;
  for (std::size_t i = 0; i < series.size(); ++i) {
    const Series& s = series[i];
    if (s.label.empty()) continue;
    const double cy = y + 4.0 + (k++ + 0.5) * row;
    const Rgb c = colour_of(s, static_cast<int>(i));
    if (s.line) {
      set_colour(cr, c);
      cairo_set_line_width(cr, s.line_width);
      if (s.dashed) {
        const double d[] = {5.0, 3.0};
        cairo_set_dash(cr, d, 2, 0.0);
      } else {
        cairo_set_dash(cr, nullptr, 0, 0.0);
      }
      cairo_move_to(cr, x + 4.0, cy);
      cairo_line_to(cr, x + 26.0, cy);
      cairo_stroke(cr);
      cairo_set_dash(cr, nullptr, 0, 0.0);
    }
    draw_marker(cr, marker_of(s, static_cast<int>(i)), x + 15.0, cy, c);
    fig.text(x + 32.0, cy + kLegendSize * 0.36, s.label, kLegendSize);
  }
  cairo_restore(cr);
}

}  // namespace

Rgb series_colour(int index) {
  // Okabe-Ito colours (yellow replaced by olive, which reads on white), then black.
  static const Rgb palette[] = {{0.000, 0.447, 0.698}, {0.835, 0.369, 0.000}, {0.000, 0.620, 0.451}, {0.800, 0.475, 0.655},
                                {0.902, 0.624, 0.000}, {0.337, 0.706, 0.914}, {0.600, 0.600, 0.200}, {0.000, 0.000, 0.000}};
  return palette[((index % 8) + 8) % 8];
}

double ChartFrame::px(double x) const {
  if (!drawable(x, log_x)) return std::numeric_limits<double>::quiet_NaN();
  const double a = axis_value(x0, log_x), b = axis_value(x1, log_x);
  return left + (axis_value(x, log_x) - a) / (b - a) * (right - left);
}

double ChartFrame::py(double y) const {
  if (!drawable(y, log_y)) return std::numeric_limits<double>::quiet_NaN();
  const double a = axis_value(y0, log_y), b = axis_value(y1, log_y);
  return bottom - (axis_value(y, log_y) - a) / (b - a) * (bottom - top);
}

std::vector<double> axis_ticks(double lo, double hi, bool log, int target, bool integers) {
  std::vector<double> t;
  if (!(hi > lo)) return t;
  if (log) {
    if (!(lo > 0.0)) return t;
    const double a = std::log10(lo), b = std::log10(hi);
    const int d0 = static_cast<int>(std::ceil(a - kTickSlack)), d1 = static_cast<int>(std::floor(b + kTickSlack));
    const int decades = d1 - d0 + 1;
    if (decades >= 2) {
      const int every = std::max(1, static_cast<int>(std::ceil(decades / static_cast<double>(std::max(1, target + 2)))));
      for (int d = d0 - ((d0 % every) + every) % every; d <= d1; d += every)
        if (d >= d0) t.push_back(std::pow(10.0, d));
      return t;
    }
    // Within about one decade: 1, 2, 5 x 10^k.
    for (int d = static_cast<int>(std::floor(a)) - 1; d <= static_cast<int>(std::ceil(b)); ++d)
      for (double m : {1.0, 2.0, 5.0}) {
        const double v = m * std::pow(10.0, d);
        if (v >= lo * (1 - kTickSlack) && v <= hi * (1 + kTickSlack)) t.push_back(v);
      }
    return t;
  }
  const double step = linear_step(lo, hi, target, integers);
  const double first = std::ceil(lo / step - kTickSlack);
  // A range too narrow for its values' precision has no ticks (k + 1 == k beyond 2^53 never ends).
  if (!(std::fabs(first) < kMaxTickIndex) || !((hi - lo) / step < kMaxTickIndex)) return t;
  for (double k = first; k * step <= hi + step * kTickSlack; k += 1.0) t.push_back(k * step);
  return t;
}

ChartFrame chart_frame(Figure& fig, const ChartBox& box, const std::vector<Series>& series, const ChartOptions& options) {
  return layout(fig, box, series, options).frame;
}

ChartFrame draw_line_chart(Figure& fig, const ChartBox& box, const std::vector<Series>& series, const ChartOptions& o) {
  const Layout L = layout(fig, box, series, o);
  const ChartFrame& f = L.frame;
  cairo_t* cr = fig.context();
  cairo_save(cr);
  // Grid lines and tick marks.
  cairo_set_line_width(cr, 1.0);
  for (double t : L.x_ticks) {
    const double x = std::round(f.px(t)) + 0.5;
    set_colour(cr, kGridColour);
    cairo_move_to(cr, x, f.top);
    cairo_line_to(cr, x, f.bottom);
    cairo_stroke(cr);
    set_colour(cr, kAxisColour);
    cairo_move_to(cr, x, f.bottom);
    cairo_line_to(cr, x, f.bottom + 5);
    cairo_stroke(cr);
    fig.text(f.px(t), f.bottom + 8.0 + kTickSize, tick_label(t, o.log_x, L.x_step), kTickSize, Align::Centre);
  }
  for (double t : L.y_ticks) {
    const double y = std::round(f.py(t)) + 0.5;
    set_colour(cr, kGridColour);
    cairo_move_to(cr, f.left, y);
    cairo_line_to(cr, f.right, y);
    cairo_stroke(cr);
    set_colour(cr, kAxisColour);
    cairo_move_to(cr, f.left - 5, y);
    cairo_line_to(cr, f.left, y);
    cairo_stroke(cr);
    fig.text(f.left - 8.0, f.py(t) + kTickSize * 0.36, tick_label(t, o.log_y, L.y_step), kTickSize, Align::Right);
  }
  // Series, clipped to the plot area.
  cairo_save(cr);
  cairo_rectangle(cr, f.left, f.top, f.right - f.left, f.bottom - f.top);
  cairo_clip(cr);
  for (std::size_t i = 0; i < series.size(); ++i) {
    const Series& s = series[i];
    const Rgb c = colour_of(s, static_cast<int>(i));
    if (s.line) {
      set_colour(cr, c);
      cairo_set_line_width(cr, s.line_width);
      cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
      if (s.dashed) {
        const double d[] = {5.0, 3.0};
        cairo_set_dash(cr, d, 2, 0.0);
      }
      bool pen = false;
      cairo_new_path(cr);
      for (std::size_t k = 0; k < s.x.size(); ++k) {
        const double x = f.px(s.x[k]), y = f.py(s.y[k]);
        if (std::isnan(x) || std::isnan(y)) {
          pen = false;
          continue;
        }
        if (pen) cairo_line_to(cr, x, y);
        else cairo_move_to(cr, x, y);
        pen = true;
      }
      cairo_stroke(cr);
      cairo_set_dash(cr, nullptr, 0, 0.0);
    }
    const Marker m = marker_of(s, static_cast<int>(i));
    for (std::size_t k = 0; k < s.x.size(); ++k) {
      const double x = f.px(s.x[k]), y = f.py(s.y[k]);
      if (!std::isnan(x) && !std::isnan(y)) draw_marker(cr, m, x, y, c);
    }
  }
  cairo_restore(cr);
  // Frame, labels, title.
  set_colour(cr, kAxisColour);
  cairo_set_line_width(cr, 1.0);
  cairo_rectangle(cr, std::round(f.left) + 0.5, std::round(f.top) + 0.5, std::round(f.right) - std::round(f.left),
                  std::round(f.bottom) - std::round(f.top));
  cairo_stroke(cr);
  cairo_restore(cr);
  if (!o.title.empty()) fig.text(box.x + box.width / 2.0, box.y + 8.0 + kTitleSize, o.title, kTitleSize, Align::Centre, true);
  const double xl_y = f.bottom + 8.0 + kTickSize + 8.0 + kLabelSize;
  if (!o.x_label.empty()) fig.text((f.left + f.right) / 2.0, xl_y, o.x_label, kLabelSize, Align::Centre);
  if (!o.note.empty())
    fig.text((f.left + f.right) / 2.0, xl_y + (o.x_label.empty() ? 0.0 : 6.0 + kNoteSize), o.note, kNoteSize, Align::Centre);
  if (!o.y_label.empty()) fig.text(box.x + 10.0 + kLabelSize, (f.top + f.bottom) / 2.0, o.y_label, kLabelSize, Align::Centre, false, M_PI / 2);
  draw_legend(fig, L, series, o);
  return f;
}

ChartFrame draw_line_chart(const std::vector<Series>& series, const ChartOptions& options, const std::string& png_path) {
  Figure fig(options.width, options.height);
  const ChartFrame f = draw_line_chart(fig, ChartBox{0, 0, options.width, options.height}, series, options);
  fig.save_png(png_path);
  return f;
}

}  // namespace icobrdf::plot
