// write_material_samples_csv (icobrdf/io/sample_draws.hpp): f is evaluated once per draw, also when the
// draws span several blocks and are checked before anything is written; the written weights are those of
// MaterialSampler::sample for the documented uniform numbers; a failure writes nothing.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <sstream>
#include <string>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/material_sampler.hpp"
#include "icobrdf/io/sample_draws.hpp"
#include "tests/support/unity_id.hpp"

using namespace icobrdf;

namespace ICOBRDF_UNITY_ID {

// Angles are printed in degrees from the drawn direction: a round trip through atan2 and the decimal text.
constexpr double kAngleTolDegrees = 1e-9;

// A source that counts the pairs it evaluates and gives NaN from the pair numbered `nan_from` on.
class CountingSource : public BrdfSource {
 public:
  explicit CountingSource(long long nan_from = -1) : inner_(open_source("model:lambert:albedo=0.5")), nan_from_(nan_from) {}
  std::string spec() const override { return "counting"; }
  int channels() const override { return 1; }
  Eigen::MatrixXd eval(const RowMatrix3d& wi, const RowMatrix3d& wr) const override {
    Eigen::MatrixXd f = inner_->eval(wi, wr);
    for (Eigen::Index i = 0; i < f.rows(); ++i)
      if (nan_from_ >= 0 && pairs_ + i >= nan_from_) f(i, 0) = std::nan("");
    pairs_ += wr.rows();
    return f;
  }
  Spectrum fit(const ProjectionContext& ctx, const FitOptions& options) const override { return inner_->fit(ctx, options); }
  long long pairs() const { return pairs_; }

 private:
  std::unique_ptr<BrdfSource> inner_;
  long long nan_from_;
  mutable std::atomic<long long> pairs_{0};
};

const Eigen::Vector3d kWi = direction_from_angles(30 * M_PI / 180, 0);

TEST(SampleDraws, FIsEvaluatedOncePerDrawOverSeveralBlocks) {
  auto source = std::make_shared<CountingSource>();
  const MaterialSampler sampler(source, 2);
  const long long per_distribution = (sampler.distribution(kWi), source->pairs());
  const long long n = 2 * kSampleDrawBlock + 1000;  // three blocks, the last one short
  std::ostringstream out;
  const long long before = source->pairs();
  ASSERT_TRUE(write_material_samples_csv(out, sampler, kWi, n, 7));
  EXPECT_EQ(source->pairs() - before, per_distribution + n) << "f evaluated more than once per draw";
  // The same draws in one call of sample(), from the documented uniform numbers.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  Eigen::VectorXd u1(n), u2(n);
  for (long long i = 0; i < n; ++i) u1[i] = uniform(rng), u2[i] = uniform(rng);
  const MaterialSamples expected = sampler.sample(kWi, u1, u2);
  std::istringstream in(out.str());
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line, "theta_r,phi_r,pdf,weight");
  long long i = 0;
  for (; std::getline(in, line); ++i) {
    ASSERT_LT(i, n);
    double theta = 0, phi = 0, pdf = 0, weight = 0;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf", &theta, &phi, &pdf, &weight), 4) << line;
    const Angles a = angles_from_direction(expected.directions.row(i).transpose());
    ASSERT_NEAR(theta, a.theta * 180 / M_PI, kAngleTolDegrees) << "draw " << i;
    ASSERT_NEAR(phi, a.phi * 180 / M_PI, kAngleTolDegrees) << "draw " << i;
    ASSERT_EQ(pdf, expected.pdf[i]) << "draw " << i;  // shortest round-trip decimals read back exactly
    ASSERT_EQ(weight, expected.weight(i, 0)) << "draw " << i;
  }
  EXPECT_EQ(i, n);
}

TEST(SampleDraws, ANonFiniteWeightInALaterBlockWritesNothing) {
  auto probe = std::make_shared<CountingSource>();
  const long long per_distribution = (MaterialSampler(probe, 2).distribution(kWi), probe->pairs());
  // NaN from draw 70,000 on (the second block): found in the first pass, before the header is written.
  auto source = std::make_shared<CountingSource>(per_distribution + 70000);
  const MaterialSampler sampler(source, 2);
  std::ostringstream out;
  try {
    write_material_samples_csv(out, sampler, kWi, 3 * kSampleDrawBlock, 7);
    FAIL() << "a NaN weight was written";
  } catch (const UnsupportedError& e) {
    EXPECT_NE(std::string(e.what()).find("the weight of draw 70000 is nan"), std::string::npos) << e.what();
  }
  EXPECT_EQ(out.str(), "");
}

TEST(SampleDraws, AnUnwritableTemporaryFolderWritesNothing) {
  const char* old = std::getenv("TMPDIR");
  const std::string kept = old ? old : "";
  ::setenv("TMPDIR", "/proc/no-such-folder", 1);
  auto source = std::make_shared<CountingSource>();
  const MaterialSampler sampler(source, 2);
  std::ostringstream out;
  EXPECT_THROW(write_material_samples_csv(out, sampler, kWi, 2 * kSampleDrawBlock, 7), IoError);
  if (old) ::setenv("TMPDIR", kept.c_str(), 1);
  else ::unsetenv("TMPDIR");
  EXPECT_EQ(out.str(), "");
}

TEST(SampleDraws, MoreWeightsThanTheTemporaryFolderHoldsAreRefusedBeforeAnyDraw) {
  // 1e17 draws of one channel need 800 PB of weights: refused before the first draw (f evaluated for the
  // distribution only), nothing written.
  constexpr long long kDraws = 100'000'000'000'000'000;
  auto source = std::make_shared<CountingSource>();
  const MaterialSampler sampler(source, 2);
  const long long per_distribution = (sampler.distribution(kWi), source->pairs());
  const long long before = source->pairs();
  std::ostringstream out;
  try {
    write_material_samples_csv(out, sampler, kWi, kDraws, 7);
    FAIL() << "800 PB of weights were accepted";
  } catch (const ResourceError& e) {
    EXPECT_NE(std::string(e.what()).find("(100000000000000000 draws x 1 channel(s)) needs about 800 PB of disk space in "), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(source->pairs() - before, per_distribution) << "f evaluated at a draw";
  EXPECT_EQ(out.str(), "");
}

}  // namespace ICOBRDF_UNITY_ID
