// Pictures checked by pixel where the answer is known: the Lambert slice is constant over the disk, the
// mirror slice peaks at the mirror direction, the Lambertian sphere follows cos(theta) of the light (and the
// sky adds sky * albedo), and bad requests leave no file.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/lambert_map.hpp"
#include "icobrdf/core/fit/spectral_fit.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/mesh/tessellation.hpp"
#include "icobrdf/plot/colormap.hpp"
#include "icobrdf/plot/disk_raster.hpp"
#include "icobrdf/plot/figure.hpp"
#include "icobrdf/plot/plots.hpp"
#include "icobrdf/plot/slice_data.hpp"
#include "icobrdf/plot/sphere_shading.hpp"
#include "tests/plot/plot_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf::plot {
namespace ICOBRDF_UNITY_ID {

using test::TempDir;

constexpr double kPi = 3.14159265358979323846;
// One step of 8-bit quantization: a colour computed in double precision and rounded to a byte differs from
// the test's own rounding of the same value by at most this.
constexpr int kByteTolerance = 1;
// Level-4 equal-area cells: 4 pi / (20 4^4) sr each, i.e. an angular size of about sqrt(that) = 0.0495 rad.
const double kCellAngle = std::sqrt(4.0 * kPi / (20.0 * 256.0));
// Half the diagonal of a sphere pixel in units of 1/size of the unit square [-1, 1]^2 (sqrt(2) x 2 / 2): a pixel
// whose centre lies closer than this to the outline is partly backdrop (anti-aliased outline).
const double kPixelHalfDiagonal = std::sqrt(2.0);

bool exists(const std::string& p) { return access(p.c_str(), F_OK) == 0; }

// A model as `icobrdf plot` hands it to the pictures (cli/cmd_plot.cpp): fitted at `order` on the
// equal-area grid of `level` (g form when it has delta parts), and as itself when it has none.
struct LoadedModel {
  std::shared_ptr<const BrdfSource> source;
  Spectrum spectrum;
  PairFunction exact;
};
LoadedModel load_model(const std::string& text, int order, int level) {
  LoadedModel m;
  m.source = open_source(text);
  const auto ctx = make_projection_context(std::make_shared<const Grid>(build_fitting_grid(level, GridKind::EqualArea, false)), order);
  FitOptions o;
  o.order = order;
  o.cosine = m.source->has_delta();
  m.spectrum = m.source->fit(ctx, o);
  if (!m.source->has_delta()) m.exact = [src = m.source](const RowMatrix3d& wi, const RowMatrix3d& wr) { return src->eval(wi, wr); };
  return m;
}
SliceSource slice_source(const std::string& text, const SliceRequest& q, int level) {
  const LoadedModel m = load_model(text, *std::max_element(q.orders.begin(), q.orders.end()), level);
  return {text, m.spectrum, m.exact};
}
std::vector<SphereMaterial> sphere_material(const std::string& text, int order, int level) {
  const LoadedModel m = load_model(text, order, level);
  SphereMaterial s;
  s.name = text;
  s.spectrum = m.spectrum;
  s.model = m.exact;
  s.model_channels = m.source->channels();
  return {s};
}

std::array<int, 3> bytes(const Rgb& c) {
  return {static_cast<int>(std::lround(c[0] * 255)), static_cast<int>(std::lround(c[1] * 255)), static_cast<int>(std::lround(c[2] * 255))};
}

void expect_close(const std::array<int, 3>& got, const std::array<int, 3>& want, int tol, const std::string& where) {
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], want[k], tol) << where << " channel " << k;
}

TEST(PlotSlice, LambertIsConstantOverTheDisk) {
  TempDir d;
  SliceRequest q;
  q.theta_i = 30.0 * kPi / 180.0;
  q.orders = {0, 2, 4};
  q.exact = false;
  q.panel = 120;
  const auto f = plot_slice(slice_source("model:lambert:albedo=0.8", q, 3), q, d.file("lambert.png"));
  // f = albedo / pi everywhere; the projection of a constant is exact up to the grid's Gram error.
  constexpr double kScaleTolerance = 1e-6;  // relative, >> the level-3 Gram error of order 4 yet far below a colour step
  EXPECT_NEAR(f.scale, 0.8 / kPi, kScaleTolerance * 0.8 / kPi);
  EXPECT_FALSE(f.g_form);
  const PngImage img = read_png(d.file("lambert.png"));
  EXPECT_EQ(img.width, f.width);
  EXPECT_EQ(img.height, f.height);
  ASSERT_EQ(f.disks.size(), 3u);
  EXPECT_FALSE(f.signed_map);  // a positive BRDF is drawn on the sequential map
  const auto want = bytes(sequential(1.0));  // every value equals the scale
  const Eigen::Vector3d wi(std::sin(q.theta_i), 0.0, std::cos(q.theta_i));
  const Eigen::Vector2d pin = lambert_to_disk(wi), pmir(-pin.x(), pin.y());
  int checked = 0;
  for (const auto& r : f.disks) {
    const double R = r.size / 2.0;
    for (int i = 0; i < r.size; i += 3)
      for (int j = 0; j < r.size; j += 3) {
        const Eigen::Vector2d p = disk_pixel_centre(r.size, i, j);
        if (p.norm() > 0.9) continue;  // keep clear of the rim line
        // keep clear of the incident ring (radius 5) and the mirror reticle (arms to 8 sqrt(2) = 11.3 px, plus
        // line width and antialiasing)
        if ((p - pin).norm() * R < 14.0 || (p - pmir).norm() * R < 14.0) continue;
        // keep clear of the theta rings at 30 and 60 degrees (radius sqrt(2) sin(theta/2)) and their labels
        // (lower right quadrant)
        if (std::fabs(p.norm() - std::sqrt(2.0) * std::sin(kPi / 12)) * R < 3.0 ||
            std::fabs(p.norm() - std::sqrt(2.0) * std::sin(kPi / 6)) * R < 3.0 || (p.x() > 0.0 && p.y() < 0.0))
          continue;
        expect_close(img.at(r.x + j, r.y + i), want, kByteTolerance, "pixel " + std::to_string(i) + "," + std::to_string(j));
        ++checked;
      }
  }
  EXPECT_GT(checked, 700);
}

TEST(PlotSlice, MirrorPeaksAtTheMirrorDirection) {
  TempDir d;
  for (double theta_deg : {22.5, 45.0, 67.5}) {
    SliceRequest q;
    q.theta_i = theta_deg * kPi / 180.0;
    q.phi_i = 30.0 * kPi / 180.0;
    q.orders = {8};
    q.panel = 200;
    const auto f = plot_slice(slice_source("model:mirror", q, 4), q, d.file("mirror.png"));
    EXPECT_TRUE(f.g_form);  // delta models are fitted and drawn as g = f cos(theta_i)
    const PngImage img = read_png(d.file("mirror.png"));
    const auto& r = f.disks.at(0);
    // The brightest pixel of the disk (the warm end of the map is the lightest colour).
    int bi = -1, bj = -1, best = -1;
    for (int i = 0; i < r.size; ++i)
      for (int j = 0; j < r.size; ++j) {
        if (disk_pixel_centre(r.size, i, j).norm() > 0.97) continue;
        const auto& c = img.at(r.x + j, r.y + i);
        const int sum = c[0] + c[1] + c[2];
        if (sum > best) best = sum, bi = i, bj = j;
      }
    ASSERT_GE(bi, 0);
    const Eigen::Vector3d w = lambert_from_disk(disk_pixel_centre(r.size, bi, bj));
    // Mirror of (theta, phi) is (theta, phi + pi).
    const Eigen::Vector3d m(-std::sin(q.theta_i) * std::cos(q.phi_i), -std::sin(q.theta_i) * std::sin(q.phi_i), std::cos(q.theta_i));
    const double angle = std::acos(std::clamp(w.dot(m), -1.0, 1.0));
    // "within a cell or two": the band-limited kernel's peak sits at the mirror direction only up to the
    // grid's discretization.
    EXPECT_LT(angle, 2.0 * kCellAngle) << "theta_i " << theta_deg << ": peak " << angle << " rad from the mirror direction";
    // The peak is drawn near the top of the colour map (the scale also covers the polar curve's samples).
    const auto top = bytes(diverging(0.9));
    EXPECT_GE(best, top[0] + top[1] + top[2]);
  }
}

// Pixel centre -> sphere normal, derived independently of the library (header's camera definition).
Eigen::Vector3d normal_at(int size, int i, int j) {
  const double x = -1.0 + (2.0 * j + 1.0) / size, y = 1.0 - (2.0 * i + 1.0) / size;
  return {x, y, std::sqrt(std::max(0.0, 1.0 - x * x - y * y))};
}

TEST(PlotSphere, LambertFollowsCosineOfTheLight) {
  TempDir d;
  constexpr double kAlbedo = 0.8;
  for (const std::string shading : {"model", "spectrum"}) {
    SphereRequest q;
    q.light_theta = 40.0 * kPi / 180.0;
    q.light_phi = 120.0 * kPi / 180.0;
    q.size = 128;
    q.shading = shading == "model" ? SphereRequest::Shading::Model : SphereRequest::Shading::Spectrum;
    const auto f = plot_sphere("model:lambert:albedo=0.8", sphere_material("model:lambert:albedo=0.8", 4, 3), q, d.file("sphere.png"));
    const PngImage img = read_png(d.file("sphere.png"));
    ASSERT_EQ(f.spheres.size(), 1u);
    const auto& r = f.spheres[0];
    const Eigen::Vector3d L(std::sin(q.light_theta) * std::cos(q.light_phi), std::sin(q.light_theta) * std::sin(q.light_phi),
                            std::cos(q.light_theta));
    int lit = 0, dark = 0;
    for (int i = 2; i < r.size; i += 9)
      for (int j = 2; j < r.size; j += 9) {
        const double x = -1.0 + (2.0 * j + 1.0) / r.size, y = 1.0 - (2.0 * i + 1.0) / r.size;
        if (std::hypot(x, y) + kPixelHalfDiagonal / r.size > 1.0) continue;  // outline pixels blend with the backdrop
        // Radiance of a Lambertian under irradiance E = pi: L = albedo * max(0, n . light).
        const double c = std::max(0.0, normal_at(r.size, i, j).dot(L));
        const int v = static_cast<int>(std::lround(srgb_encode(kAlbedo * c) * 255));
        expect_close(img.at(r.x + j, r.y + i), {v, v, v}, kByteTolerance + (shading == "spectrum" ? 1 : 0),
                     shading + " pixel " + std::to_string(i) + "," + std::to_string(j));
        (c > 0 ? lit : dark)++;
      }
    EXPECT_GT(lit, 50);
    EXPECT_GT(dark, 10);
  }
}

TEST(PlotSphere, SkyAddsSkyRadianceTimesAlbedo) {
  TempDir d;
  for (const std::string shading : {"model", "spectrum"}) {
    SphereRequest q;
    q.light_theta = kPi;  // light straight behind the sphere: only the sky reaches the visible side
    q.sky = 0.5;
    q.size = 64;
    q.shading = shading == "model" ? SphereRequest::Shading::Model : SphereRequest::Shading::Spectrum;
    const auto f = plot_sphere("model:lambert:albedo=0.6", sphere_material("model:lambert:albedo=0.6", 2, 3), q, d.file("sky.png"));
    const PngImage img = read_png(d.file("sky.png"));
    const auto& r = f.spheres[0];
    // Directional albedo of a Lambertian = its albedo, so L = 0.5 * 0.6 everywhere. The model path uses a
    // midpoint rule over level-3 cells for the albedo integral (error well below one colour step).
    const int v = static_cast<int>(std::lround(srgb_encode(0.5 * 0.6) * 255));
    for (int i = 4; i < r.size; i += 7)
      for (int j = 4; j < r.size; j += 7) {
        const double x = -1.0 + (2.0 * j + 1.0) / r.size, y = 1.0 - (2.0 * i + 1.0) / r.size;
        if (std::hypot(x, y) + kPixelHalfDiagonal / r.size > 1.0) continue;  // outline pixels blend with the backdrop
        expect_close(img.at(r.x + j, r.y + i), {v, v, v}, kByteTolerance, shading);
      }
  }
}

TEST(PlotSphere, LocalFrameIsOrthonormalAndRightHanded) {
  for (const Eigen::Vector3d& n : {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0.6, 0.0, 0.8), Eigen::Vector3d(0.0, 0.6, 0.8),
                                  Eigen::Vector3d(0.3, -0.4, std::sqrt(0.75))}) {
    const Eigen::Matrix3d f = sphere_local_frame(n);
    constexpr double kRounding = 1e-14;  // a few ulps of unit vectors
    EXPECT_LT((f * f.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), kRounding);
    EXPECT_NEAR(f.determinant(), 1.0, kRounding);
    EXPECT_LT((f.row(2).transpose() - n).norm(), kRounding);
  }
  // At the centre of the picture the tangent is +x (stated in the header).
  EXPECT_LT((sphere_local_frame(Eigen::Vector3d::UnitZ()).row(0).transpose() - Eigen::Vector3d::UnitX()).norm(), 1e-15);
}

TEST(PlotErrors, BadRequestsLeaveNoFile) {
  TempDir d;
  SliceRequest q;
  q.theta_i = 95.0 * kPi / 180.0;
  q.orders = {2};
  const SliceSource lambert = slice_source("model:lambert", q, 2);
  EXPECT_THROW(plot_slice(lambert, q, d.file("a.png")), ArgumentError);
  EXPECT_FALSE(exists(d.file("a.png")));
  q.theta_i = 0.5;
  EXPECT_THROW(plot_slice(slice_source("model:no-such-model", q, 2), q, d.file("b.png")), ArgumentError);
  EXPECT_FALSE(exists(d.file("b.png")));
  EXPECT_THROW(plot_slice(lambert, q, d.file("missing-folder/c.png")), IoError);
  EXPECT_FALSE(exists(d.file("missing-folder/c.png")));
  SphereRequest s;
  s.shading = SphereRequest::Shading::Model;
  // delta models have no model shading
  EXPECT_THROW(plot_sphere("model:mirror", sphere_material("model:mirror", 2, 2), s, d.file("d.png")), ArgumentError);
  EXPECT_FALSE(exists(d.file("d.png")));
  EXPECT_THROW(plot_basis(3, d.file("no-dir"), false), ArgumentError);
  // Only the files named above were ever attempted: the folder holds nothing (no temporaries either).
  EXPECT_EQ(std::system(("test -z \"$(ls -A '" + d.path + "')\"").c_str()), 0);
}

}  // namespace
}  // namespace icobrdf::plot
