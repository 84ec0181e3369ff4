// Samples over their fit, checked by content: the samples in a plane of incidence are drawn (their group's colour
// at each marker's centre in both panels), the others are not, their abscissae are their signed theta_r, the
// residual panel lies below with its zero line and labels, and the residual RMS counts every sample; on the
// PTFE and CURET fixtures the groups are the files' own incidence angles and the fit leaves the residual the
// published fit leaves.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <string>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/plot/figure.hpp"
#include "icobrdf/plot/plot_options.hpp"
#include "icobrdf/plot/sample_plot.hpp"
#include "tests/plot/plot_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf::plot {
namespace ICOBRDF_UNITY_ID {

using test::TempDir;
using test::byte_distance;

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
// Rounding of a few operations on doubles of order one (angles from acos / atan2 of unit vectors).
constexpr double kRounding = 1e-9;
// A filled marker's centre pixel against its colour: antialiasing reaches only its rim (radius 3.6 pixels).
constexpr int kMarkerBytes = 3;
// Two panels' plot areas start and end at frame positions rounded to whole pixels each.
constexpr double kAxisPixels = 1.0;
// A pixel of text or of an axis: every channel below this (the page is white, the grid light grey).
constexpr int kDarkByte = 110;

Eigen::RowVector3d dir(double theta_deg, double phi_deg) {
  const double t = theta_deg * kDeg, p = phi_deg * kDeg;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

int dark_pixels(const PngImage& img, int x0, int y0, int x1, int y1) {
  int n = 0;
  for (int y = std::max(0, y0); y < std::min(img.height, y1); ++y)
    for (int x = std::max(0, x0); x < std::min(img.width, x1); ++x) {
      const auto& p = img.at(x, y);
      n += p[0] < kDarkByte && p[1] < kDarkByte && p[2] < kDarkByte;
    }
  return n;
}

TEST(PlotSamples, InPlaneSamplesAreDrawnWithTheirResiduals) {
  // A Lambertian fit, f = 1/pi everywhere, and samples at theta_i = 30 degrees, phi_i = 0 (values inside the
  // axis ranges, none on a frame line): two on the forward
  // side (phi_r = 180), one on the backward side (phi_r = 0), one 3 degrees off the plane (drawn) and one at
  // phi_r = 90 (not drawn, yet counted in the RMS).
  const double f = 1.0 / kPi;
  SampleSet s;
  const double tr[] = {20, 50, 40, 60, 45}, pr[] = {180, 180, 0, 183, 90}, v[] = {0.22, 0.43, 0.30, 0.36, 0.5};
  s.wi.resize(5, 3);
  s.wr.resize(5, 3);
  s.values.resize(5);
  for (int k = 0; k < 5; ++k) s.wi.row(k) = dir(30, 0), s.wr.row(k) = dir(tr[k], pr[k]), s.values(k) = v[k];
  const PairFunction lambert = [f](const RowMatrix3d& wi, const RowMatrix3d&) { return Eigen::MatrixXd::Constant(wi.rows(), 1, f); };
  TempDir d;
  const SamplePlotFigure fig = plot_samples("lambert", s, lambert, "the Lambertian 1/pi", {}, d.file("s.png"));
  ASSERT_EQ(fig.points.size(), 4u);
  ASSERT_EQ(fig.group_theta_deg.size(), 1u);
  EXPECT_NEAR(fig.group_theta_deg[0], 30.0, kRounding);
  const double expected_x[] = {20, 50, -40, 60};
  double sum2 = 0.0;
  for (double x : v) sum2 += (x - f) * (x - f);
  EXPECT_NEAR(fig.residual_rms, std::sqrt(sum2 / 5), kRounding);
  const PngImage img = read_png(d.file("s.png"));
  ASSERT_EQ(img.width, fig.width);
  const Rgb colour = sample_group_colour(0);
  for (std::size_t k = 0; k < fig.points.size(); ++k) {
    const SamplePoint& p = fig.points[k];
    EXPECT_EQ(p.sample, static_cast<Eigen::Index>(k));
    EXPECT_NEAR(p.x_deg, expected_x[k], kRounding);
    EXPECT_NEAR(p.fit, f, kRounding);
    EXPECT_LE(byte_distance(img.at(static_cast<int>(p.value_px), static_cast<int>(p.value_py)), colour), kMarkerBytes) << "sample " << k;
    EXPECT_LE(byte_distance(img.at(static_cast<int>(p.residual_px), static_cast<int>(p.residual_py)), colour), kMarkerBytes) << "residual " << k;
    // Positive residuals sit above the zero line, negative ones below.
    EXPECT_EQ(p.residual_py < fig.residuals.py(0.0), v[k] > f) << "residual " << k;
    EXPECT_NEAR(p.residual_px, p.value_px, kAxisPixels);  // one x axis for both panels
  }
  // The residual panel lies below the values; both carry tick labels and a y label at their left, and the
  // x label below.
  EXPECT_GT(fig.residuals.top, fig.values.bottom);
  for (const ChartFrame* c : {&fig.values, &fig.residuals}) {
    EXPECT_GT(dark_pixels(img, 0, static_cast<int>(c->top), static_cast<int>(c->left) - 6, static_cast<int>(c->bottom)), 20);  // y label, ticks
    EXPECT_GT(dark_pixels(img, static_cast<int>(c->left), static_cast<int>(c->bottom) + 20, static_cast<int>(c->right),
                          static_cast<int>(c->bottom) + 45),
              20);  // the x label
  }
}

TEST(PlotSamples, RefusesSamplesOffEveryPlane) {
  SampleSet s;
  s.wi = dir(30, 0);
  s.wr = dir(40, 90);
  s.values = Eigen::VectorXd::Constant(1, 0.3);
  const PairFunction one = [](const RowMatrix3d& wi, const RowMatrix3d&) { return Eigen::MatrixXd::Constant(wi.rows(), 1, 0.3); };
  TempDir d;
  EXPECT_THROW(plot_samples("x", s, one, "one", {}, d.file("x.png")), ArgumentError);
  EXPECT_NE(access(d.file("x.png").c_str(), F_OK), 0);
}

TEST(PlotSamples, PtfeAndCuretGroupsAreTheirIncidenceAngles) {
  TempDir d;
  // tests/data/measured/README.md: NIST's PTFE at theta_i = 0 (0.001), 15, ..., 75 degrees; Germer's own
  // order-7 fit leaves an RMS of 0.00299 1/sr at these samples.
  const SamplePicture p = load_sample_picture(std::string(ICOBRDF_SOURCE_DIR) + "/tests/data/measured/ptfe532.csv", -1, 2);
  const SamplePlotFigure f = plot_samples("ptfe", p.samples, p.fit, p.fit_label, {}, d.file("p.png"));
  ASSERT_EQ(f.group_theta_deg.size(), 6u);
  for (std::size_t g = 0; g < 6; ++g) EXPECT_NEAR(f.group_theta_deg[g], 15.0 * static_cast<double>(g), 0.01);
  // A least-squares fit of the same samples with its order chosen by cross-validation: within 20 % of it.
  constexpr double kPublishedRms = 0.00299, kFitSlack = 1.2;
  EXPECT_LT(f.residual_rms, kPublishedRms * kFitSlack);
  EXPECT_EQ(f.total, p.samples.values.size());
  // CURET's in-plane geometries (tests/data/measured/table.txt) lie at multiples of 11.25 degrees.
  const SamplePicture c = load_sample_picture("curet:" + std::string(ICOBRDF_SOURCE_DIR) + "/tests/data/measured/abrdf.dat#sample=5", -1, 2);
  const SamplePlotFigure cf = plot_samples("curet", c.samples, c.fit, c.fit_label, {}, d.file("c.png"));
  ASSERT_FALSE(cf.group_theta_deg.empty());
  for (double t : cf.group_theta_deg) EXPECT_NEAR(std::remainder(t, 11.25), 0.0, 0.5) << t;
  EXPECT_THROW(load_sample_picture("model:lambert", -1, 2), ArgumentError);
}

TEST(PlotOptions, RequestsTakeDegreesAndNamesAndRefuseOtherForms) {
  const SphereRequest sphere = sphere_request("30,90", 0.3, 2.0, 128, "spectrum");
  EXPECT_NEAR(sphere.light_theta, 30 * kDeg, kRounding);
  EXPECT_NEAR(sphere.light_phi, 90 * kDeg, kRounding);
  EXPECT_EQ(sphere.sky, 0.3);
  EXPECT_EQ(sphere.exposure, 2.0);
  EXPECT_EQ(sphere.size, 128);
  EXPECT_EQ(sphere.shading, SphereRequest::Shading::Spectrum);
  EXPECT_THROW(sphere_request("30", 0, 1, 128, "auto"), ArgumentError);
  const SliceRequest slice = slice_request(45, -90, "none", 150, false, true);
  EXPECT_NEAR(slice.theta_i, 45 * kDeg, kRounding);
  EXPECT_NEAR(slice.phi_i, -90 * kDeg, kRounding);
  EXPECT_EQ(slice.panel, 150);
  EXPECT_FALSE(slice.exact);
  EXPECT_TRUE(slice.log);
  EXPECT_THROW(slice_request(45, 0, "boxcar", 150, true, false), ArgumentError);
  try {
    load_spectrum_picture("model:lambert");
    FAIL() << "a model was taken for a spectrum file";
  } catch (const ArgumentError& e) {
    EXPECT_STREQ(e.what(), "plot spectrum 'model:lambert': expected SPECTRUM.h5[#material]");
  }
}

}  // namespace
}  // namespace icobrdf::plot
