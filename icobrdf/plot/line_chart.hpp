#pragma once
// Line charts: several (x, y) series with markers, a legend, labelled axes (linear or base-10 log),
// tick labels and a light grid, drawn with cairo into a Figure (icobrdf/plot/figure.hpp) or straight to a PNG.
//
//   std::vector<Series> s{{"level 3", {0, 1, 2}, {0.3, 0.1, 0.02}}};
//   ChartOptions o;  o.title = "..."; o.x_label = "order"; o.y_label = "relative L2 error"; o.log_y = true;
//   draw_line_chart(s, o, "error.png");
//
// Data: x[k], y[k] pairs (equal lengths, else ArgumentError). A point that cannot be drawn (non-finite, or
// <= 0 on a log axis) is skipped and breaks the series' line there. Points outside a fixed axis range are
// clipped to the plot area.
// Axis ranges (NaN = automatic): linear axes span the finite data widened to the enclosing tick step;
// log axes span whole decades around the data. An empty or degenerate range is widened ([v - 1, v + 1],
// or one decade each way on a log axis).
// Pixel geometry: ChartFrame maps data to pixels (plot-area corners at the pixel edges left/top and
// right/bottom); the point (x, y) is drawn centred at (frame.px(x), frame.py(y)).
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "icobrdf/plot/colormap.hpp"
#include "icobrdf/plot/figure.hpp"

namespace icobrdf::plot {

enum class Marker { Auto, None, Circle, Square, Triangle, Diamond, Cross };

struct Series {
  std::string label;        // legend entry; empty = not listed
  std::vector<double> x, y;
  Rgb colour{-1.0, -1.0, -1.0};  // a component < 0: the palette colour of the series' index
  Marker marker = Marker::Auto;  // Auto: a shape by index (circle, square, triangle, diamond, cross)
  bool line = true;              // join consecutive drawable points
  bool dashed = false;
  double line_width = 1.8;
};

enum class LegendPlace { Right, TopRight, BottomLeft, None };  // Right: outside the plot area

struct ChartOptions {
  std::string title, x_label, y_label;
  bool log_x = false, log_y = false;
  int width = 720, height = 460;  // PNG size (draw_line_chart to a file)
  double x_min = std::numeric_limits<double>::quiet_NaN(), x_max = std::numeric_limits<double>::quiet_NaN();
  double y_min = std::numeric_limits<double>::quiet_NaN(), y_max = std::numeric_limits<double>::quiet_NaN();
  LegendPlace legend = LegendPlace::Right;
  bool integer_x = false;  // linear x ticks at integers only (orders, levels)
  std::string note;        // one line of small text under the x label (caption), optional
};

// The i-th colour of the palette (8 colours distinguishable in colour-blind vision, then repeating).
Rgb series_colour(int index);

// Data -> pixel mapping of a drawn chart.
struct ChartFrame {
  double left = 0, top = 0, right = 0, bottom = 0;  // plot area in pixels
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;              // axis range in data units
  bool log_x = false, log_y = false;
  double px(double x) const;  // NaN for a value a log axis cannot show
  double py(double y) const;
};

// A rectangle of a figure (pixels) a chart is drawn into: title, axes, labels and legend all inside it.
struct ChartBox {
  int x = 0, y = 0, width = 0, height = 0;
};

// The frame draw_line_chart would use for these series in this box (ranges, margins), without drawing.
ChartFrame chart_frame(Figure& fig, const ChartBox& box, const std::vector<Series>& series, const ChartOptions& options);

// Draws into `box` of `fig` (several charts per figure: one box each) and returns the frame used.
ChartFrame draw_line_chart(Figure& fig, const ChartBox& box, const std::vector<Series>& series, const ChartOptions& options);

// One chart of options.width x options.height written to `png_path` (atomically, icobrdf/plot/figure.hpp).
ChartFrame draw_line_chart(const std::vector<Series>& series, const ChartOptions& options, const std::string& png_path);

// Tick values of an axis range: linear "nice" steps (1, 2, 5 x 10^k, about `target` ticks; integers only
// when `integers`), or on a log axis powers of ten (every k-th decade when there are many; 1, 2, 5 within a
// single decade).
std::vector<double> axis_ticks(double lo, double hi, bool log, int target = 6, bool integers = false);

}  // namespace icobrdf::plot
