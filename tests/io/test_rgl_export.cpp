// RGL tensor-file export (icobrdf/io/rgl_export.hpp), read back by the RGL reader (icobrdf/io/rgl_bsdf.hpp):
// agreement with the source in the cosine metric, the microfacet tables against independent quadratures,
// and the refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "icobrdf/core/models/function_model.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/rgl_bsdf.hpp"
#include "icobrdf/io/rgl_export.hpp"
#include "icobrdf/io/tensor_file.hpp"
#include "tests/io/io_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

using icobrdf::test::ScratchDir;
using namespace icobrdf;

// The export's agreement target in the cosine metric (the RGL export's acceptance figure).
constexpr double kExportAgreement = 0.03;
// Independent quadrature of sigma and of the projected area of D: midpoint rules in theta (4000 points) and
// phi (720 points); the phi rule crosses the kink of max(0, w_i . m) with an error of order (2 pi / 720)^2.
constexpr double kQuadratureTol = 1e-4;
constexpr int kPairs = 20000;

struct Pairs {
  RowMatrix3d wi, wr;
};
// Uniform in solid angle on both hemispheres.
Pairs uniform_pairs(int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Pairs p{RowMatrix3d(n, 3), RowMatrix3d(n, 3)};
  for (int k = 0; k < n; ++k)
    for (RowMatrix3d* w : {&p.wi, &p.wr}) {
      const double z = u(rng), phi = 2 * M_PI * u(rng), s = std::sqrt(1 - z * z);
      w->row(k) << s * std::cos(phi), s * std::sin(phi), z;
    }
  return p;
}

Eigen::MatrixXd values(const BrdfModel& m, const RowMatrix3d& wi, const RowMatrix3d& wr) {
  Eigen::MatrixXd out(wi.rows(), m.channels());
  m.eval(wi, wr, out);
  return out;
}

// |cos cos (f_file - f)| / |cos cos f|, the source's channel 0 against every channel of the file.
double cosine_l2(const Eigen::MatrixXd& file, const Eigen::MatrixXd& f, const Pairs& p) {
  double num = 0, den = 0;
  for (Eigen::Index r = 0; r < file.rows(); ++r) {
    const double w = p.wi(r, 2) * p.wr(r, 2);
    for (Eigen::Index c = 0; c < file.cols(); ++c) {
      const double s = f(r, f.cols() == 1 ? 0 : c);
      num += w * w * (file(r, c) - s) * (file(r, c) - s);
      den += w * w * s * s;
    }
  }
  return std::sqrt(num / den);
}

double export_agreement(const std::string& spec, const ScratchDir& d) {
  const auto model = parse_model(spec);
  const std::string path = d / "x.bsdf";
  write_rgl_export(path, *model, {});
  const RglModel back(std::make_shared<const RglBsdf>(read_rgl_bsdf(path)), {0, 1, 2}, path);
  const Pairs p = uniform_pairs(kPairs, 7);
  return cosine_l2(values(back, p.wi, p.wr), values(*model, p.wi, p.wr), p);
}

TEST(RglExport, GlossyModelsReadBackWithinTheAgreementTarget) {
  ScratchDir d;
  for (const std::string spec : {"ggx:alpha=0.3,f0=0.04", "0.8*lambert:albedo=0.5+0.2*ggx:alpha=0.2,f0=0.04"}) {
    const double e = export_agreement(spec, d);
    EXPECT_LE(e, kExportAgreement) << spec;
    std::printf("[ figures  ] RGL export of %s read back: cosine-weighted relative L2 %.4g\n", spec.c_str(), e);
  }
}

// The ndf's projected area and sigma(theta_i) of the written file, against midpoint quadratures over
// (theta, phi) of the file's own D (bilinear in u_theta = sqrt(2 theta / pi)).
TEST(RglExport, NdfHasUnitProjectedAreaAndSigmaIsItsProjection) {
  ScratchDir d;
  const std::string path = d / "g.bsdf";
  write_rgl_export(path, *parse_model("ggx:alpha=0.3,f0=0.04"), {});
  const TensorFile tf = read_tensor_file(path);
  const std::vector<double> ndf = tf.find("ndf")->values(), sigma = tf.find("sigma")->values();
  const int n = static_cast<int>(tf.find("ndf")->shape[1]);
  const auto row = [n](const std::vector<double>& t, double theta) {
    const double x = std::sqrt(2 * theta / M_PI) * (n - 1);
    const int k = std::min(static_cast<int>(x), n - 2);
    return t[static_cast<size_t>(k)] + (x - k) * (t[static_cast<size_t>(k + 1)] - t[static_cast<size_t>(k)]);
  };
  const int nt = 4000, np = 720;
  std::vector<double> cos_phi(np);
  for (int b = 0; b < np; ++b) cos_phi[static_cast<size_t>(b)] = std::cos((b + 0.5) * 2 * M_PI / np);
  const auto projected = [&](double theta_i) {  // integral of D(m) max(0, w_i . m) dw_m
    double acc = 0;
    for (int a = 0; a < nt; ++a) {
      const double th = (a + 0.5) * (M_PI / 2) / nt, dm = row(ndf, th), st = std::sin(th);
      const double x = std::sin(theta_i) * st, z = std::cos(theta_i) * std::cos(th);
      double ring = 0;
      for (double c : cos_phi) ring += std::max(0.0, x * c + z);
      acc += dm * ring * st;
    }
    return acc * (M_PI / 2 / nt) * (2 * M_PI / np);
  };
  EXPECT_NEAR(projected(0.0), 1.0, kQuadratureTol);
  for (const double theta_i : {0.5, 1.0, 1.4}) EXPECT_NEAR(row(sigma, theta_i), projected(theta_i), kQuadratureTol) << theta_i;
}

TEST(RglExport, WritesTheShapesMitsubaReads) {
  ScratchDir d;
  const std::string path = d / "s.bsdf";
  RglExportOptions o;
  o.theta_nodes = 5;
  o.value_resolution = 16;
  o.vndf_resolution = 24;
  o.ndf_resolution = 20;
  const RglExportSummary s = write_rgl_export(path, *parse_model("ggx:alpha=0.3"), o);
  const RglBsdf b = read_rgl_bsdf(path);
  EXPECT_TRUE(b.isotropic());
  EXPECT_TRUE(b.jacobian);
  EXPECT_FALSE(b.spectral);
  ASSERT_EQ(b.theta_i.size(), 5u);
  EXPECT_EQ(b.theta_i.front(), 0.0);
  EXPECT_NEAR(b.theta_i.back(), M_PI / 2, 1e-7);  // float32 of pi/2
  EXPECT_NEAR(std::cos(b.theta_i[2]), 0.5, 1e-7);  // uniform in cos theta_i
  EXPECT_EQ(b.sample_width, 16);
  EXPECT_EQ(b.sample_height, 16);
  EXPECT_EQ(b.vndf.width(), 24);
  EXPECT_EQ(b.ndf.width(), 20);
  EXPECT_EQ(b.ndf.height(), 2);
  EXPECT_GT(s.bytes, 0);
}

TEST(RglExport, RefusesBadOptionsAndNonFiniteSourcesWithoutWriting) {
  ScratchDir d;
  RglExportOptions o;
  o.value_resolution = 1;
  EXPECT_THROW(write_rgl_export(d / "o.bsdf", *parse_model("lambert"), o), ArgumentError);
  const FunctionModel two(2, [](const RowMatrix3d&, const RowMatrix3d&, Eigen::Ref<Eigen::MatrixXd> out) { out.setConstant(0.1); }, "two",
                          true, true);
  EXPECT_THROW(write_rgl_export(d / "t.bsdf", two, {}), ArgumentError);
  const FunctionModel nan(1, [](const RowMatrix3d& wi, const RowMatrix3d&, Eigen::Ref<Eigen::MatrixXd> out) {
    for (Eigen::Index r = 0; r < out.rows(); ++r) out(r, 0) = wi(r, 2) < 0.5 ? std::nan("") : 0.3;
  }, "nan-at-grazing", true, true);
  try {
    write_rgl_export(d / "n.bsdf", nan, {});
    ADD_FAILURE() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nan-at-grazing: f is"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(d.entries().empty());
}

}  // namespace ICOBRDF_UNITY_ID
