// plot/line_chart: data land on the pixels the axis definitions give, ticks follow the 1-2-5 / decade rules,
// undrawable points break lines, bad series are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>
#include <unistd.h>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/plot/figure.hpp"
#include "icobrdf/plot/line_chart.hpp"
#include "tests/support/unity_id.hpp"

using namespace icobrdf;
using namespace icobrdf::plot;

namespace ICOBRDF_UNITY_ID {

// Markers and lines are antialiased: a pixel counts as "the series colour" within this many sRGB levels.
constexpr int kColourTol = 40;
// Marker radius 3.6 px (icobrdf/plot/line_chart.cpp), squares of side 7.2 px: every pixel of the marker lies
// within 3.6 * sqrt(2) + 1 (antialiased edge) < 6.5 px of its centre.
constexpr double kMarkerReach = 6.5;
// A filled 7.2 px square covers at least 6 x 6 pixels fully.
constexpr int kMinMarkerPixels = 36;

bool near_colour(const std::array<int, 3>& p, const std::array<int, 3>& c) {
  return std::abs(p[0] - c[0]) <= kColourTol && std::abs(p[1] - c[1]) <= kColourTol && std::abs(p[2] - c[2]) <= kColourTol;
}

std::string temp_png(const std::string& stem) { return "/tmp/icobrdf_line_chart_" + stem + "_" + std::to_string(::getpid()) + ".png"; }

TEST(LineChart, MarkerOnLogAxesLandsAtTheDecadeMidpoint) {
  // log10(10) is halfway between log10(1) and log10(100); log10(1e-3) halfway between -6 and 0:
  // the point (10, 1e-3) must be drawn at the centre of the plot area.
  Series s{"", {10.0}, {1e-3}};
  s.colour = {1.0, 0.0, 0.0};
  s.marker = Marker::Square;
  s.line = false;
  ChartOptions o;
  o.log_x = o.log_y = true;
  o.x_min = 1, o.x_max = 100, o.y_min = 1e-6, o.y_max = 1;
  o.legend = LegendPlace::None;
  o.title = "t";
  o.x_label = "x";
  o.y_label = "y";
  const std::string path = temp_png("marker");
  const ChartFrame f = draw_line_chart({s}, o, path);
  const double cx = (f.left + f.right) / 2, cy = (f.top + f.bottom) / 2;
  EXPECT_NEAR(f.px(10.0), cx, 1e-9);
  EXPECT_NEAR(f.py(1e-3), cy, 1e-9);
  const PngImage img = read_png(path);
  std::remove(path.c_str());
  ASSERT_EQ(img.width, o.width);
  ASSERT_EQ(img.height, o.height);
  const std::array<int, 3> red{255, 0, 0};
  EXPECT_TRUE(near_colour(img.at(static_cast<int>(cx), static_cast<int>(cy)), red));
  int count = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      if (near_colour(img.at(x, y), red)) {
        ++count;
        EXPECT_LT(std::hypot(x + 0.5 - cx, y + 0.5 - cy), kMarkerReach) << x << "," << y;
      }
  EXPECT_GE(count, kMinMarkerPixels);
}

TEST(LineChart, LinearAxesPutTheMidpointOfADiagonalAtTheCentre) {
  // y = x from (0, 0) to (10, 10) on [0, 10] x [0, 10] passes through the centre of the plot area.
  Series s{"diagonal", {0.0, 10.0}, {0.0, 10.0}};
  s.colour = {0.0, 0.0, 1.0};
  s.marker = Marker::None;
  s.line_width = 5.0;
  ChartOptions o;
  o.x_min = 0, o.x_max = 10, o.y_min = 0, o.y_max = 10;
  Figure fig(500, 400);
  const ChartFrame f = draw_line_chart(fig, ChartBox{0, 0, 500, 400}, {s}, o);
  const double cx = (f.left + f.right) / 2, cy = (f.top + f.bottom) / 2;
  EXPECT_NEAR(f.px(5.0), cx, 1e-9);
  EXPECT_NEAR(f.py(5.0), cy, 1e-9);
  EXPECT_TRUE(near_colour(fig.pixel(static_cast<int>(cx), static_cast<int>(cy)), {0, 0, 255}));
  // A quarter of the way along the x axis at mid height lies off the line (y = x gives 2.5 there, not 5).
  EXPECT_FALSE(near_colour(fig.pixel(static_cast<int>(f.px(2.5)), static_cast<int>(cy)), {0, 0, 255}));
}

TEST(LineChart, UndrawablePointsBreakTheLine) {
  // (1, 1), (2, 0), (3, 1) on a log y axis: y = 0 cannot be drawn, so no segment joins (1, 1) and (3, 1);
  // the pixel at (2, 1) must stay background. Without the gap the line y = 1 would cross it.
  Series s{"", {1.0, 2.0, 3.0}, {1.0, 0.0, 1.0}};
  s.colour = {0.0, 0.6, 0.0};
  s.marker = Marker::None;
  s.line_width = 4.0;
  ChartOptions o;
  o.log_y = true;
  o.x_min = 0, o.x_max = 4, o.y_min = 0.1, o.y_max = 10;
  o.legend = LegendPlace::None;
  Figure fig(400, 300);
  const ChartFrame f = draw_line_chart(fig, ChartBox{0, 0, 400, 300}, {s}, o);
  EXPECT_FALSE(near_colour(fig.pixel(static_cast<int>(f.px(2.0)), static_cast<int>(f.py(1.0))), {0, 153, 0}));
  // Control: the same series with the middle point drawable does cross (2, 1).
  s.y[1] = 1.0;
  Figure fig2(400, 300);
  const ChartFrame f2 = draw_line_chart(fig2, ChartBox{0, 0, 400, 300}, {s}, o);
  EXPECT_TRUE(near_colour(fig2.pixel(static_cast<int>(f2.px(2.0)), static_cast<int>(f2.py(1.0))), {0, 153, 0}));
}

TEST(LineChart, AutomaticRangesAreWholeDecadesAndTickSteps) {
  Figure fig(600, 400);
  ChartOptions o;
  o.log_y = true;
  // y in [3e-5, 0.2] -> decades [1e-5, 1]; x in [0, 17] -> nice step 5 (17/6 = 2.8 -> 5) -> [0, 20].
  const ChartFrame f = chart_frame(fig, ChartBox{0, 0, 600, 400}, {Series{"a", {0, 17}, {3e-5, 0.2}}}, o);
  EXPECT_DOUBLE_EQ(f.y0, 1e-5);
  EXPECT_DOUBLE_EQ(f.y1, 1.0);
  EXPECT_DOUBLE_EQ(f.x0, 0.0);
  EXPECT_DOUBLE_EQ(f.x1, 20.0);
}

TEST(LineChart, TicksFollowTheOneTwoFiveAndDecadeRules) {
  // [0, 20], about 7 integer ticks: 20/7 = 2.86 -> step 5.
  EXPECT_EQ(axis_ticks(0, 20, false, 7, true), (std::vector<double>{0, 5, 10, 15, 20}));
  // [0, 1], about 6 ticks: 1/6 = 0.167 -> step 0.2; compare within rounding of k * 0.2.
  const auto t = axis_ticks(0, 1, false, 6, false);
  ASSERT_EQ(t.size(), 6u);
  for (std::size_t k = 0; k < t.size(); ++k) EXPECT_NEAR(t[k], 0.2 * k, 1e-15);
  // [1e-6, 1]: 7 decades, at most target + 2 = 8 labels -> every decade.
  const auto d = axis_ticks(1e-6, 1, true, 6, false);
  ASSERT_EQ(d.size(), 7u);
  for (std::size_t k = 0; k < d.size(); ++k) EXPECT_NEAR(std::log10(d[k]), -6.0 + k, 1e-12);
  // [1e-16, 1]: 17 decades for 8 labels -> every ceil(17/8) = 3rd decade, on multiples of 3: 1e-15 ... 1.
  const auto e = axis_ticks(1e-16, 1, true, 6, false);
  ASSERT_EQ(e.size(), 6u);
  for (std::size_t k = 0; k < e.size(); ++k) EXPECT_NEAR(std::log10(e[k]), -15.0 + 3.0 * k, 1e-12);
  // Within one decade [2, 9]: 1-2-5 multiples inside the range are 2 and 5.
  EXPECT_EQ(axis_ticks(2, 9, true, 6, false), (std::vector<double>{2, 5}));
}

TEST(LineChart, ValuesEqualToRoundingAreDrawnFlat) {
  // A Lambertian spectrum's in-plane curve at normal incidence: 0.5 / pi, and the same plus 1 ulp. Before,
  // the axis took the 1-ulp spread for its range, ticks 5e-18 apart were counted beyond 2^53 (k + 1 == k)
  // and the program filled 16 GB. Now: drawn flat around the value, [0, 2 v], with a handful of ticks.
  const double v = 0.5 / M_PI, w = std::nextafter(v, 1.0);
  Figure fig(400, 300);
  const ChartFrame f = draw_line_chart(fig, ChartBox{0, 0, 400, 300}, {Series{"a", {0, 1, 2}, {v, w, v}}}, ChartOptions{});
  EXPECT_LE(f.y0, 0.0 + 1e-12);
  EXPECT_GE(f.y1, 2 * v - 1e-12);
  EXPECT_LT(f.y1, 2 * v + 0.2);  // the next nice tick above 2 v
  // A range too narrow for its values' precision gives no ticks (and returns).
  EXPECT_TRUE(axis_ticks(v, w, false, 6, false).empty());
}

TEST(LineChart, MismatchedSeriesAndDegenerateRangesAreRefused) {
  Figure fig(400, 300);
  EXPECT_THROW(draw_line_chart(fig, ChartBox{0, 0, 400, 300}, {Series{"bad", {1, 2}, {1}}}, ChartOptions{}), ArgumentError);
  ChartOptions o;
  o.x_min = 2, o.x_max = 1;
  EXPECT_THROW(draw_line_chart(fig, ChartBox{0, 0, 400, 300}, {Series{"a", {1}, {1}}}, o), ArgumentError);
  ChartOptions l;
  l.log_x = true;
  l.x_min = -1;
  EXPECT_THROW(draw_line_chart(fig, ChartBox{0, 0, 400, 300}, {Series{"a", {1}, {1}}}, l), ArgumentError);
  EXPECT_THROW(draw_line_chart(fig, ChartBox{0, 0, 50, 50}, {Series{"a", {1}, {1}}}, ChartOptions{}), ArgumentError);
}

TEST(LineChart, EmptyChartStillDrawsItsAxes) {
  // No drawable data: default ranges [-1, 1] (linear) / [0.1, 10] (log), nothing thrown.
  ChartOptions o;
  o.log_y = true;
  Figure fig(400, 300);
  const ChartFrame f = draw_line_chart(fig, ChartBox{0, 0, 400, 300}, {Series{"none", {1.0}, {0.0}}}, o);
  EXPECT_DOUBLE_EQ(f.y0, 0.1);
  EXPECT_DOUBLE_EQ(f.y1, 10.0);
}

}  // namespace ICOBRDF_UNITY_ID
