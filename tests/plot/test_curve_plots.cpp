// The measured-data pictures checked by content: colour scales (sequential for a positive BRDF, diverging
// only for signed data, log positions), a slice drawn from a source's own values without any fit, in-plane
// curves that peak where the model peaks, the directional albedo of a Lambertian, the spectrum's scale set
// without its DC coefficient, and the basis written to a FILE.png.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/pipeline/picture_source.hpp"
#include "icobrdf/plot/colormap.hpp"
#include "icobrdf/plot/curve_plots.hpp"
#include "icobrdf/plot/disk_raster.hpp"
#include "icobrdf/plot/figure.hpp"
#include "icobrdf/plot/half_diff_plot.hpp"
#include "icobrdf/plot/plot_options.hpp"
#include "icobrdf/plot/plots.hpp"
#include "icobrdf/plot/value_scale.hpp"
#include "tests/plot/plot_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf::plot {
namespace ICOBRDF_UNITY_ID {

using test::TempDir;
using test::byte_distance;

constexpr double kPi = 3.14159265358979323846;
// Rounding of a few operations on doubles of order one.
constexpr double kRounding = 1e-12;
// Two steps of 8-bit quantization: the drawn colour against the map's colour rounded by the test.
constexpr int kColourBytes = 2;
// A line's antialiased pixels against its colour: the core of a 1.8-pixel line is within this of it, the
// page's other colours (grid, text, other series) far beyond.
constexpr int kLineBytes = 40;

PairFunction values_of(const std::string& text) {
  std::shared_ptr<const BrdfSource> s = open_source(text);
  return [s](const RowMatrix3d& wi, const RowMatrix3d& wr) { return s->eval(wi, wr); };
}

// The position t in [0, 1] of the sequential map nearest to a drawn colour, and how far (bytes) it is.
std::pair<double, int> nearest_sequential(const std::array<int, 3>& c) {
  double best_t = 0.0;
  int best = 1 << 20;
  for (int k = 0; k <= 1000; ++k) {
    const int d = byte_distance(c, sequential(k / 1000.0));
    if (d < best) best = d, best_t = k / 1000.0;
  }
  return {best_t, best};
}

TEST(ValueScale, PositiveDataAreSequentialSignedDataDiverging) {
  Eigen::MatrixXd pos(1, 3), sig(1, 3), tiny(1, 2);
  pos << 0.0, 0.5, 2.0;
  sig << -0.5, 0.1, 2.0;
  tiny << -kSignedShare * 0.5, 1.0;  // rounding-size negative values do not make data signed
  const ValueScale a = value_scale({&pos}, false), b = value_scale({&sig}, false), c = value_scale({&tiny}, false);
  EXPECT_FALSE(a.is_signed);
  EXPECT_TRUE(b.is_signed);
  EXPECT_FALSE(c.is_signed);
  EXPECT_DOUBLE_EQ(a.top, 2.0);
  EXPECT_NEAR(a.unit(2.0), 1.0, kRounding);  // the whole sequential range is used: top -> 1, zero -> 0
  EXPECT_NEAR(a.unit(0.0), 0.0, kRounding);
  EXPECT_NEAR(b.unit(-2.0), -1.0, kRounding);
  // Log over kDefaultDecades decades: a value 10^-d below the top sits at 1 - d / decades.
  const ValueScale l = value_scale({&pos}, true);
  EXPECT_NEAR(l.unit(2.0 * 1e-2), 1.0 - 2.0 / kDefaultDecades, kRounding);
  EXPECT_NEAR(l.unit(0.0), 0.0, kRounding);
  // Signed log: odd, and value_at inverts unit.
  const ValueScale sl = value_scale({&sig}, true);
  for (double v : {-1.5, -0.01, 1e-5, 0.3, 2.0}) {
    EXPECT_NEAR(sl.unit(-v), -sl.unit(v), kRounding);
    EXPECT_NEAR(sl.value_at(sl.unit(v)), v, kRounding * 10);
  }
  // Ticks of a positive linear scale stay within [0, top] and include 0.
  const auto t = a.ticks();
  ASSERT_FALSE(t.empty());
  EXPECT_EQ(t.front(), 0.0);
  EXPECT_LE(t.back(), 2.0);
}

TEST(PlotSliceValues, APositiveModelUsesTheWholeSequentialMapWithoutAFit) {
  TempDir d;
  // Values only: the source is not fitted (no spectrum), and the slice draws one column of the values.
  const PictureMaterial m = load_picture_material("model:ggx:alpha=0.3", 8, 4, true);
  EXPECT_FALSE(m.spectrum.has_value());
  ASSERT_TRUE(static_cast<bool>(m.exact));
  SliceRequest q;
  q.theta_i = 45.0 * kPi / 180.0;
  q.orders = {};
  q.panel = 120;
  const SliceFigure f = plot_slice({"ggx", std::nullopt, m.exact, "model"}, q, d.file("ggx.png"));
  EXPECT_FALSE(f.signed_map);
  ASSERT_EQ(f.disks.size(), 1u);
  const PngImage img = read_png(d.file("ggx.png"));
  const auto& r = f.disks[0];
  double lo = 1.0, hi = 0.0;
  int on_map = 0, off_map = 0;
  for (int i = 0; i < r.size; i += 2)
    for (int j = 0; j < r.size; j += 2) {
      if (disk_pixel_centre(r.size, i, j).norm() > 0.85) continue;
      const auto [t, dist] = nearest_sequential(img.at(r.x + j, r.y + i));
      if (dist > kColourBytes) {  // markers, rings and labels drawn over the disk
        ++off_map;
        continue;
      }
      ++on_map;
      lo = std::min(lo, t);
      hi = std::max(hi, t);
    }
  EXPECT_GT(on_map, 5 * off_map);
  // GGX at 45 degrees: a peak near the mirror direction, values near zero at the far side: more than half the
  // map is in use (a symmetric map would leave half of it unused).
  EXPECT_GT(hi - lo, 0.5);
  EXPECT_LT(lo, 0.1);  // the dark end of the map is in use (on a symmetric map zero would sit mid-way)
}

TEST(PlotSliceValues, MeasuredFileSliceNeedsNoOrder) {
  std::vector<int> orders{0, 2};
  // A model named without orders is still fitted (cheap); its orders stay.
  const SliceSource s = load_slice_source("model:lambert", orders, false, 2);
  EXPECT_TRUE(s.spectrum.has_value());
  EXPECT_EQ(orders.size(), 2u);
  SliceRequest q;
  q.orders = {};  // no order and no values of its own: nothing to draw
  EXPECT_THROW(plot_slice(SliceSource{"none", std::nullopt, {}, "model"}, q, "/tmp/never.png"), ArgumentError);
  EXPECT_NE(access("/tmp/never.png", F_OK), 0);
}

TEST(PlotCurves, GgxPeaksAtTheMirrorAngle) {
  TempDir d;
  CurveRequest q;
  q.theta_i = {30.0 * kPi / 180.0};
  const CurveFigure f = plot_curves("ggx", values_of("model:ggx:alpha=0.2"), "f", q, d.file("c.png"));
  const PngImage img = read_png(d.file("c.png"));
  const Rgb c = series_colour(0);
  // The highest pixel of the series' colour in the Cartesian chart lies at theta_r = +30 degrees (forward side).
  int best_y = 1 << 20, best_x = -1;
  for (int y = static_cast<int>(f.cartesian.top); y < static_cast<int>(f.cartesian.bottom); ++y)
    for (int x = static_cast<int>(f.cartesian.left); x < static_cast<int>(f.cartesian.right); ++x)
      if (byte_distance(img.at(x, y), c) <= kLineBytes && y < best_y) best_y = y, best_x = x;
  ASSERT_GE(best_x, 0);
  constexpr double kPeakPixels = 4.0;  // line width and antialiasing around the drawn peak
  EXPECT_NEAR(best_x, f.cartesian.px(30.0), kPeakPixels);
  // The polar curve's farthest point from the origin lies along 30 degrees on the forward (left) side.
  double far = 0.0, angle = 0.0;
  for (int y = 0; y < img.height; ++y)
    for (int x = static_cast<int>(f.polar_cx - f.polar_radius); x < img.width; ++x)
      if (byte_distance(img.at(x, y), c) <= kLineBytes && y < f.polar_cy) {
        const double dx = x - f.polar_cx, dy = f.polar_cy - y, r = std::hypot(dx, dy);
        if (r > far) far = r, angle = std::atan2(-dx, dy) * 180.0 / kPi;
      }
  constexpr double kAngleDegrees = 2.0;  // a few pixels at the peak's radius
  EXPECT_NEAR(angle, 30.0, kAngleDegrees);
  EXPECT_NEAR(far, f.polar_radius, kPeakPixels);  // the peak is the scale's top
}

TEST(PlotAlbedo, LambertianAlbedoIsItsAlbedoAtEveryAngle) {
  TempDir d;
  const AlbedoFigure f = plot_albedo("lambert", values_of("model:lambert:albedo=0.6"), 1, {}, 0.0, d.file("a.png"));
  ASSERT_EQ(f.theta_i_deg.size(), 45u);  // 0, 2, ..., 88
  // The midpoint rule of cos(theta) over equal-area cells of level 4: error far below 1e-3 (cos varies by
  // about 2.8 degrees across a cell, the first-order errors cancel within a cell).
  constexpr double kQuadrature = 1e-3;
  for (double a : f.albedo[0]) EXPECT_NEAR(a, 0.6, kQuadrature);
  // The curve is drawn at a = 0.6 mid-way along theta_i.
  const PngImage img = read_png(d.file("a.png"));
  const int x = static_cast<int>(std::lround(f.frame.px(45.0))), y = static_cast<int>(std::lround(f.frame.py(0.6)));
  int nearest = 1 << 20;
  for (int dy = -3; dy <= 3; ++dy) nearest = std::min(nearest, byte_distance(img.at(x, y + dy), series_colour(0)));
  EXPECT_LE(nearest, kLineBytes);
}

TEST(PlotSpectrumScale, TheDcCoefficientIsShownApart) {
  TempDir d;
  // A mostly diffuse material (as measured white samples are): its DC coefficient dwarfs the rest.
  const PictureMaterial m = load_picture_material("model:lambert+0.1*ggx", 4, 3);
  ASSERT_TRUE(m.spectrum.has_value());
  const SpectrumFigure f = plot_spectrum(*m.spectrum, "ggx", d.file("s.png"));
  const Eigen::VectorXd a = ibsss_from_coefficients(m.spectrum->channels[0]);
  double rest = 0.0;
  for (Eigen::Index k = 1; k < a.size(); ++k) rest = std::max(rest, std::fabs(a[k]));
  ASSERT_GT(std::fabs(a[0]), rest);  // the DC coefficient dominates ...
  EXPECT_GE(f.scale, rest * (1 - kRounding));  // ... and the scale is that of the others
  EXPECT_LT(f.scale, std::fabs(a[0]));
}

TEST(PlotBasisOutput, AFileOrAFolder) {
  TempDir d;
  const auto files = plot_basis(2, d.file("pyramid.png"), false);
  ASSERT_EQ(files.size(), 1u);
  EXPECT_EQ(files[0], d.file("pyramid.png"));
  EXPECT_EQ(access(d.file("pyramid.png").c_str(), F_OK), 0);
  EXPECT_EQ(plot_basis(1, d.path, false).at(0), d.path + "/basis.png");
  EXPECT_THROW(plot_basis(1, d.file("no-folder/x.png"), false), ArgumentError);
  EXPECT_THROW(plot_basis(1, d.file("no-folder"), false), ArgumentError);
}

TEST(PlotHalfDiff, PixelsAreAtTheirHalfAndDifferenceAngles) {
  constexpr int kSize = 36;
  // acos of a cosine rounded to a few ulps: about eps / sin(angle), angles >= 1.25 degrees here.
  constexpr double kAngleRounding = 1e-9;
  for (const double phi_d : {kPi / 2, 0.0, kPi / 4, -2.0})
    for (int i = 0; i < kSize; i += 5)
      for (int j = 0; j < kSize; j += 5) {
        const auto [wi, wo] = half_diff_directions(kSize, i, j, phi_d);
        const double th = (kPi / 2) * (j + 0.5) / kSize, td = (kPi / 2) * (i + 0.5) / kSize;
        const Eigen::Vector3d h = (wi + wo).normalized();
        EXPECT_NEAR(wi.norm(), 1.0, kRounding);
        EXPECT_NEAR(wo.norm(), 1.0, kRounding);
        EXPECT_NEAR(std::acos(std::clamp(h.z(), -1.0, 1.0)), th, kAngleRounding);  // theta_h: the half vector from the normal
        EXPECT_NEAR(std::acos(std::clamp(wi.dot(h), -1.0, 1.0)), td, kAngleRounding);  // theta_d: w_i from the half vector
        // phi_d: the azimuth of w_i in the frame of h (w_i turned back by theta_h about y: h to the normal).
        const Eigen::Vector2d d(wi.x() * std::cos(th) - wi.z() * std::sin(th), wi.y());
        EXPECT_NEAR(std::remainder(std::atan2(d.y(), d.x()) - phi_d, 2 * kPi), 0.0, kAngleRounding) << "phi_d " << phi_d;
      }
}

TEST(PlotHalfDiff, GgxIsBrightestAtThetaHZero) {
  TempDir d;
  const HalfDiffFigure f = plot_half_diff("ggx", values_of("model:ggx:alpha=0.2"), true, d.file("hd.png"), 120);
  EXPECT_FALSE(f.scale.is_signed);
  const PngImage img = read_png(d.file("hd.png"));
  // Along a row (fixed theta_d = 30 degrees) the map position falls as theta_h grows from 0 to 60 degrees:
  // GGX's D peaks at h = n (towards theta_h = 90, w_i and w_o graze and 1 / (cos cos) takes over).
  const int row = f.image.size / 3;
  double previous = 2.0;
  for (int j = 0; j <= f.image.size * 2 / 3; j += 10) {
    const auto [t, dist] = nearest_sequential(img.at(f.image.x + j, f.image.y + row));
    ASSERT_LE(dist, kColourBytes) << "column " << j;
    constexpr double kMapStep = 0.01;  // positions of colours a byte apart on the map
    EXPECT_LE(t, previous + kMapStep) << "column " << j;
    previous = t;
  }
  // From theta_h ~ 0 to 60 degrees D falls by more than a decade (alpha = 0.2): more than a quarter of the
  // 4-decade map.
  const double at0 = nearest_sequential(img.at(f.image.x, f.image.y + row)).first;
  const double at60 = nearest_sequential(img.at(f.image.x + f.image.size * 2 / 3, f.image.y + row)).first;
  EXPECT_GT(at0 - at60, 0.25);
}

}  // namespace
}  // namespace icobrdf::plot
