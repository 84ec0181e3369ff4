// The pieces of the bank builder (pipeline/): held-out errors, pruning, the "modes" candidate, the resume
// key, the bank written as the build goes. End-to-end builds are in tests/cli/test_bank*.cpp.
#include <gtest/gtest.h>

#include <cmath>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/helmholtz_modes.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/atomic_write.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/pipeline/bank_builder.hpp"
#include "icobrdf/pipeline/bank_resume.hpp"
#include "icobrdf/pipeline/held_out.hpp"
#include "icobrdf/pipeline/keys.hpp"
#include "icobrdf/pipeline/material_candidate.hpp"
#include "icobrdf/pipeline/pruning.hpp"
#include "tests/io/io_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

// Sums of a few products of cosines: rounding only.
constexpr double kRounding = 1e-14;

Scene small_scene() {
  Scene s;
  s.levels = {1, 2};
  s.order_max = 4;
  s.holdout_pairs = 64;
  return s;
}

SceneMaterial material(const std::string& name, const std::string& source, double target) {
  SceneMaterial m;
  m.name = name;
  m.source = source;
  m.target = target;
  return m;
}

Spectrum fitted(const BrdfSource& src, int level, int order) {
  FitRequest r;
  r.level = level;
  r.order = order;
  return fit_source(src, r).spectrum;
}

TEST(HeldOut, LightsTimesCamerasAndSeededPairs) {
  const Scene s = small_scene();
  SceneMaterial m = material("a", "model:lambert", 0.01);
  const auto src = open_source(m.source);
  EXPECT_EQ(held_out_pairs(s, m, *src).wi.rows(), 64);
  EXPECT_EQ(held_out_pairs(s, m, *src).wi, held_out_pairs(s, m, *src).wi);  // reproducible
  SceneMaterial other = m;
  other.name = "b";
  EXPECT_NE(held_out_pairs(s, other, *src).wi, held_out_pairs(s, m, *src).wi);  // seeded by the name
  m.lights = {{30, 0}, {60, 90}};
  m.cameras = {{0, 0}, {45, 180}, {70, 30}};
  const HeldOutPairs h = held_out_pairs(s, m, *src);
  EXPECT_EQ(h.wi.rows(), 6);
  EXPECT_NEAR(h.wi(0, 2), std::cos(M_PI / 6), 1e-15);
}

TEST(HeldOut, ExactSpectrumHasNoErrorAndTruncationToNothingHasRelativeErrorOne) {
  const Scene s = small_scene();
  const SceneMaterial m = material("a", "model:minnaert:k=2", 0.01);
  const auto src = open_source(m.source);
  const HeldOutPairs h = held_out_pairs(s, m, *src);
  const Spectrum spec = fitted(*src, 2, 2);  // Minnaert k = 2 is in the span at order 2
  for (const ErrorMetric metric : {ErrorMetric::F, ErrorMetric::Cosine}) {
    const HeldOutErrors errors(h, 2, metric);
    EXPECT_LT(errors(spec.channels, 2).l2, 1e-12);
    EXPECT_LT(errors(spec.channels, 2).max, 1e-12);
    std::vector<Eigen::MatrixXd> zero{Eigen::MatrixXd::Zero(6, 6)};
    EXPECT_NEAR(errors(zero, 2).l2, 1.0, 1e-15);
    EXPECT_GT(errors(truncate_channels(spec.channels, 0), 0).l2, 1e-3);
  }
}

// The share of sum w^2 f^2 from grazing pairs (theta_i or theta_r beyond 80 degrees), for a constant f on
// two lights (85 and 30 degrees) x two cameras (10, 20 degrees): the pairs of the 85-degree light are grazing.
// "f": w = 1, two of four equal terms; "cosine": the camera sums cancel, cos^2 85 / (cos^2 85 + cos^2 30).
TEST(HeldOut, GrazingShareIsTheNormFromPairsBeyondEightyDegrees) {
  const Scene s = small_scene();
  SceneMaterial m = material("a", "model:lambert", 0.01);
  m.lights = {{85, 0}, {30, 0}};
  m.cameras = {{10, 0}, {20, 90}};
  const auto src = open_source(m.source);
  const HeldOutPairs h = held_out_pairs(s, m, *src);
  EXPECT_NEAR(HeldOutErrors(h, 0, ErrorMetric::F).grazing_share(), 0.5, kRounding);
  const double c85 = std::cos(85 * M_PI / 180), c30 = std::cos(M_PI / 6);
  EXPECT_NEAR(HeldOutErrors(h, 0, ErrorMetric::Cosine).grazing_share(), c85 * c85 / (c85 * c85 + c30 * c30), kRounding);
}

TEST(Pruning, KeepsTheFewestCoefficientsMeetingTheTarget) {
  const Scene s = small_scene();
  const SceneMaterial m = material("a", "model:0.5*lambert+0.5*phong:n=3", 0.2);
  const auto src = open_source(m.source);
  const HeldOutPairs h = held_out_pairs(s, m, *src);
  const HeldOutErrors errors(h, 3, ErrorMetric::F);
  Spectrum spec = fitted(*src, 2, 3);
  const PruneResult r = prune_coefficients(spec, errors, 0.2);
  EXPECT_EQ(r.total, static_cast<int>(helmholtz_mode_count(3)));
  ASSERT_TRUE(r.pruned);
  EXPECT_LT(r.kept, r.total);
  EXPECT_LE(r.error.l2, 0.2);
  EXPECT_EQ(errors(spec.channels, 3).l2, r.error.l2);  // the spectrum is the pruned one
  Spectrum all = fitted(*src, 2, 3);
  EXPECT_EQ(prune_coefficients(all, errors, 1.0).kept, 0);  // nothing at all is within a relative error of 1
}

TEST(MaterialCandidate, ModesIsChosenWithItsBytes) {
  const Scene s = small_scene();
  const SceneMaterial m = material("a", "model:lambert", 0.001);
  const auto src = open_source(m.source);
  const HeldOutPairs h = held_out_pairs(s, m, *src);
  const HeldOutErrors errors(h, s.order_max, m.metric);
  FitContexts contexts;
  std::vector<std::string> said;
  const MaterialProblem p{s, m, *src, &errors, contexts, [&](const std::string& line) { said.push_back(line); }};
  const MaterialCandidate c = choose_representation(p);
  EXPECT_EQ(c.representation, "modes");
  EXPECT_TRUE(c.measured);
  EXPECT_TRUE(c.isotropic);  // "auto": Lambert is isotropic
  EXPECT_EQ(c.level, 1);
  EXPECT_EQ(c.order, 0);
  EXPECT_EQ(c.kept, 1);
  EXPECT_EQ(c.bytes, 1 * (8 + 12));
  EXPECT_EQ(c.record.name, "a");
  EXPECT_EQ(c.record.ibsss.cols(), isotropic_mode_count(0));
  EXPECT_FALSE(said.empty());
}

TEST(MaterialCandidate, UnreachableTargetIsTheModesError) {
  Scene s = small_scene();
  s.levels = {1};
  const SceneMaterial m = material("a", "model:ggx:alpha=0.1", 1e-6);
  const auto src = open_source(m.source);
  const HeldOutPairs h = held_out_pairs(s, m, *src);
  const HeldOutErrors errors(h, s.order_max, m.metric);
  FitContexts contexts;
  const MaterialProblem p{s, m, *src, &errors, contexts, [](const std::string&) {}};
  try {
    choose_representation(p);
    FAIL() << "no error";
  } catch (const UnsupportedError& e) {
    EXPECT_NE(std::string(e.what()).find("target 1e-06 not met"), std::string::npos) << e.what();
  }
}

TEST(BankResume, MaterialKeyIsTheTextOfTheSceneWords) {
  Scene s = small_scene();
  SceneMaterial m = material("a", "model:lambert", 0.5);
  m.metric = ErrorMetric::Cosine;
  m.isotropic = IsotropicChoice::Never;
  s.sampling = LutSampling::CellAverage;
  EXPECT_EQ(material_key(s, m), fnv1a_hex("icobrdf-bank-material-v2|a|model:lambert|0.5|false|-1|-1|cosine|0|90|prune|bank|4|4|average|64|"
                                          "nolut32|1|2|repr|modes|half-angle|hybrid"));
  EXPECT_EQ(to_string(IsotropicChoice::Auto), "auto");
  EXPECT_EQ(to_string(IsotropicChoice::Always), "true");
  EXPECT_EQ(to_string(ErrorMetric::F), "f");
  EXPECT_EQ(to_string(LutSampling::CellCentre), "centre");
}

// The resume file's pace: the first rewrite at once; later ones after max(10 x the last one's duration, 1 s).
TEST(BankResume, CheckpointIsDueAfterTenTimesTheLastRewriteAndAtLeastASecond) {
  EXPECT_TRUE(icobrdf::checkpoint_due(false, 0.0, 0.0));    // none yet: the first material is kept at once
  EXPECT_FALSE(icobrdf::checkpoint_due(true, 0.5, 0.01));   // 10 x 10 ms passed, not a second
  EXPECT_TRUE(icobrdf::checkpoint_due(true, 1.0, 0.01));    // a second
  EXPECT_FALSE(icobrdf::checkpoint_due(true, 1.9, 0.2));    // a second, not 10 x 0.2 s
  EXPECT_TRUE(icobrdf::checkpoint_due(true, 2.0, 0.2));     // 10 x 0.2 s
}

// The bank is written as the materials finish (BankCollector with icobrdf/io/bank_file.hpp BankWriter). A
// failure to write it (here injected at the second material) does not stop the build: every material is
// still fitted and kept for --resume, the build then ends with that error, and neither the bank nor its
// temporary is left.
TEST(BankBuildWriting, AFailedBankWriteKeepsEveryMaterialForResume) {
  icobrdf::test::ScratchDir dir;
  Scene scene;
  scene.level = 1;
  scene.levels = {1};
  scene.order_max = 2;
  scene.holdout_pairs = 64;
  scene.representations = {"modes"};
  for (const char* name : {"a", "b", "c"}) scene.materials.push_back(material(name, "model:lambert:albedo=0.5", 100.0));
  BankBuildOptions opt;
  opt.output = dir / "bank.h5";
  int materials_written = 0;
  set_write_fault_hook([&](const std::string& point) {
    if (point == "bank:writer-material" && ++materials_written == 2) throw IoError("injected failure writing the second material");
  });
  try {
    build_bank(scene, opt);
    ADD_FAILURE() << "the build succeeded";
  } catch (const IoError& e) {
    EXPECT_EQ(std::string(e.what()), "injected failure writing the second material");
  }
  set_write_fault_hook({});
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"bank.h5.partial"});
  EXPECT_EQ(read_bank(dir / "bank.h5.partial").materials.size(), 3u);
  // And without the failure the same scene gives its bank, resumed from the kept materials.
  opt.resume = true;
  const BankBuildResult again = build_bank(scene, opt);
  EXPECT_TRUE(again.written);
  for (const auto& m : again.materials) EXPECT_TRUE(m.resumed) << m.name;
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"bank.h5"});
}

}  // namespace
}  // namespace icobrdf
