// Glossy materials end to end: `bank build` chooses a half-angle or hybrid representation for narrow
// specular lobes, and the stored materials evaluate (icobrdf eval) within their target against the analytic
// models at direction pairs drawn here, independently of the builder's own held-out pairs.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "tests/cli/cli_runner.hpp"
#include "tests/support/unity_id.hpp"

using icobrdf::test::run_cli;
using icobrdf::test::TempDir;

namespace ICOBRDF_UNITY_ID {

// The builder measures its error on its own 4096 held-out pairs; an independent draw of 20000 pairs estimates
// the same integral with a sampling error of its own. For lobes a few degrees wide only ~1% of uniform pairs
// fall in the peak, so the two estimates differ (GGX 0.1: builder 0.0158, two independent draws 0.0148 and
// 0.0184, i.e. up to 1.17x; a single near-grazing pair can carry 20-30% of the sum); the check allows 1.5x.
constexpr double kIndependentEstimateSlack = 1.5;
constexpr double kTarget = 0.02;
constexpr int kPairs = 20000;
// Every stored representation is reciprocal by construction (symmetric C; the lobe is pi-periodic in phi_d,
// and the swap maps d to (-d_x, -d_y, d_z) exactly): what remains is the rounding of the half-angle frame.
constexpr double kReciprocityTol = 1e-12;
// Mean directional albedo of the stored material's LUT against the model's LUT on the same cells: an
// integral of the approximation error (target 0.02 in the cosine metric); a few times the target.
constexpr double kAlbedoTol = 0.05;

const char* const kScene = R"([bank]
level = 2
levels = [2, 3]
order_max = 8
target = 0.02
metric = "cosine"
sampling = "centre"
holdout_pairs = 4096

[[material]]
name = "ggx"
source = "model:ggx:alpha=0.1,f0=0.04"

[[material]]
name = "plastic"
source = "model:0.8*lambert:albedo=0.5+0.2*ggx:alpha=0.1,f0=0.04"

[[material]]
name = "aniso"
source = "model:ggx-aniso:alpha_x=0.1,alpha_y=0.3,f0=0.04"

[[material]]
name = "matte"
source = "model:lambert:albedo=0.5"
target = 0.001
)";

struct Pairs {
  std::vector<double> ti, pi, tr, pr;  // degrees
};

// Uniform in solid angle on both hemispheres: cos(theta) uniform in [0, 1], phi uniform.
Pairs draw_pairs(int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Pairs p;
  for (int k = 0; k < n; ++k) {
    p.ti.push_back(std::acos(u(rng)) * 180 / M_PI);
    p.pi.push_back(360 * u(rng));
    p.tr.push_back(std::acos(u(rng)) * 180 / M_PI);
    p.pr.push_back(360 * u(rng));
  }
  return p;
}

std::string write_pairs(const TempDir& d, const std::string& name, const Pairs& p, bool swapped) {
  std::ofstream out(d.file(name));
  out.precision(17);
  out << "theta_i,phi_i,theta_r,phi_r\n";
  for (size_t k = 0; k < p.ti.size(); ++k) {
    if (swapped) out << p.tr[k] << "," << p.pr[k] << "," << p.ti[k] << "," << p.pi[k] << "\n";
    else out << p.ti[k] << "," << p.pi[k] << "," << p.tr[k] << "," << p.pr[k] << "\n";
  }
  return d.file(name);
}

std::vector<double> eval_column(const std::string& source, const std::string& pairs) {
  const auto v = icobrdf::test::eval_first_column(source, pairs);
  EXPECT_FALSE(v.empty()) << "icobrdf eval " << source << " failed";
  return v;
}

class GlossyBank : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    std::ofstream(dir_->file("scene.toml")) << kScene;
    bank_ = dir_->file("bank.h5");
    build_ = new icobrdf::test::CliResult(run_cli({"bank", "build", dir_->file("scene.toml"), "-o", bank_}));
    pairs_ = draw_pairs(kPairs, 20261124);
    forward_ = write_pairs(*dir_, "forward.csv", pairs_, false);
    backward_ = write_pairs(*dir_, "backward.csv", pairs_, true);
  }
  static void TearDownTestSuite() {
    delete build_;
    delete dir_;
  }
  // Relative L2 error of f cos_i cos_r (the scene's metric) of the stored material against the model.
  static double independent_error(const std::string& material, const std::string& model) {
    const auto got = eval_column(bank_ + "#" + material, forward_);
    const auto want = eval_column(model, forward_);
    double num = 0, den = 0;
    for (size_t k = 0; k < want.size() && k < got.size(); ++k) {
      const double w = std::cos(pairs_.ti[k] * M_PI / 180) * std::cos(pairs_.tr[k] * M_PI / 180);
      num += std::pow(w * (got[k] - want[k]), 2);
      den += std::pow(w * want[k], 2);
    }
    EXPECT_EQ(got.size(), want.size());
    return std::sqrt(num / den);
  }
  static void check_choices();
  static void check_independent_errors();
  static void check_reciprocity();
  static void check_readers();
  static TempDir* dir_;
  static std::string bank_, forward_, backward_;
  static icobrdf::test::CliResult* build_;
  static Pairs pairs_;
};
TempDir* GlossyBank::dir_ = nullptr;
std::string GlossyBank::bank_, GlossyBank::forward_, GlossyBank::backward_;
icobrdf::test::CliResult* GlossyBank::build_ = nullptr;
Pairs GlossyBank::pairs_;

std::string table_row(const std::string& out, const std::string& name) {
  std::istringstream in(out);
  for (std::string line; std::getline(in, line);)
    if (line.rfind(name + " ", 0) == 0) return line;
  return "";
}

// One test, one bank build: CTest runs every test case in a process of its own, and the build (the anisotropic
// lobe above all) is the expensive part.
TEST_F(GlossyBank, BuildsChoosesAndEvaluatesEveryRepresentation) {
  ASSERT_EQ(build_->exit_code, 0) << build_->out << build_->err;
  {
    SCOPED_TRACE("representation chosen per material");
    check_choices();
  }
  {
    SCOPED_TRACE("errors at independently drawn pairs");
    check_independent_errors();
  }
  {
    SCOPED_TRACE("reciprocity");
    check_reciprocity();
  }
  {
    SCOPED_TRACE("bank info, spectrum, lut and albedo of stored lobes");
    check_readers();
  }
}

void GlossyBank::check_choices() {
  EXPECT_NE(build_->out.find("repr"), std::string::npos) << build_->out;
  for (const char* m : {"ggx", "plastic", "aniso"}) {
    const std::string row = table_row(build_->out, m);
    EXPECT_TRUE(row.find("half-angle") != std::string::npos || row.find("hybrid") != std::string::npos) << row;
  }
  EXPECT_NE(table_row(build_->out, "matte").find("modes"), std::string::npos) << build_->out;
  EXPECT_NE(table_row(build_->out, "aniso").find(" no "), std::string::npos) << "anisotropic lobe expected: " << build_->out;
}

void GlossyBank::check_independent_errors() {
  const struct {
    const char *material, *model;
    double target;
  } cases[] = {{"ggx", "model:ggx:alpha=0.1,f0=0.04", kTarget},
               {"plastic", "model:0.8*lambert:albedo=0.5+0.2*ggx:alpha=0.1,f0=0.04", kTarget},
               {"aniso", "model:ggx-aniso:alpha_x=0.1,alpha_y=0.3,f0=0.04", kTarget}};
  for (const auto& c : cases) EXPECT_LT(independent_error(c.material, c.model), kIndependentEstimateSlack * c.target) << c.material;
  EXPECT_LT(independent_error("matte", "model:lambert:albedo=0.5"), 0.001 * kIndependentEstimateSlack);
}

void GlossyBank::check_reciprocity() {
  for (const char* m : {"ggx", "plastic", "aniso", "matte"}) {
    const auto f = eval_column(bank_ + "#" + m, forward_), b = eval_column(bank_ + "#" + m, backward_);
    ASSERT_EQ(f.size(), b.size());
    double worst = 0, scale = 0;
    for (size_t k = 0; k < f.size(); ++k) {
      worst = std::max(worst, std::abs(f[k] - b[k]));
      scale = std::max(scale, std::abs(f[k]));
    }
    EXPECT_LE(worst, kReciprocityTol * scale) << m;
  }
}

void GlossyBank::check_readers() {
  auto r = run_cli({"bank", "info", bank_});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("icobrdf bank 4.0"), std::string::npos) << r.out;  // lobes stored compactly (docs/file-format.md)
  EXPECT_NE(r.out.find("half-angle lobe of q = f (cos_i + cos_r)/2 (isotropic), rank"), std::string::npos) << r.out;
  // The anisotropic lobe's h grid is stretched along its wide axis, y (alpha_y = 0.3 against 0.1).
  EXPECT_NE(r.out.find("(anisotropic)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("along 90.0 deg"), std::string::npos) << r.out;
  r = run_cli({"spectrum", bank_ + "#ggx"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("+ half-angle lobe"), std::string::npos) << r.out;
  // The LUT of the stored material and of the model itself on the same cells: their mean directional albedos
  // (white furnace) agree to about the target. The mean weighs incidences as the cosine metric does; the
  // largest albedo sits at grazing incidence, where that metric gives the error no weight.
  const auto albedo = [&](const std::string& source, const std::string& name) {
    auto l = run_cli({"lut", source, "--level", "3", "--order", "2", "-o", dir_->file(name)});
    EXPECT_EQ(l.exit_code, 0) << l.err;
    auto a = run_cli({"albedo", dir_->file(name), "--json"});
    EXPECT_EQ(a.exit_code, 0) << a.err;
    const auto k = a.out.find("\"mean_albedo\"");
    return k == std::string::npos ? NAN : std::stod(a.out.substr(a.out.find(':', k) + 1));
  };
  const double stored = albedo(bank_ + "#ggx", "stored.h5"), model = albedo("model:ggx:alpha=0.1,f0=0.04", "model.h5");
  EXPECT_NEAR(stored, model, kAlbedoTol * model);
}

}  // namespace
