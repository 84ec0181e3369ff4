// Byte budgets (max_bytes) and best effort (on_miss = "keep-best") in the choice of a representation
// (icobrdf/pipeline/material_candidate.hpp). End-to-end builds with a missed target are in tests/cli/test_bank.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>

#include "icobrdf/core/basis/helmholtz_modes.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/pipeline/held_out.hpp"
#include "icobrdf/pipeline/material_candidate.hpp"
#include "icobrdf/pipeline/modes_representation.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

Scene small_scene() {
  Scene s;
  s.levels = {1, 2};
  s.order_max = 4;
  s.holdout_pairs = 256;
  s.representations = {"modes"};
  return s;
}

SceneMaterial glossy(double target, long long max_bytes, OnMiss on_miss, const std::string& source = "model:ggx:alpha=0.3") {
  SceneMaterial m;
  m.name = "g";
  m.source = source;
  m.target = target;
  m.max_bytes = max_bytes;
  m.on_miss = on_miss;
  return m;
}

// One material's source, held-out pairs and errors, and the choice for it.
struct Chooser {
  const Scene& scene;
  std::unique_ptr<BrdfSource> source;
  HeldOutPairs pairs;
  std::unique_ptr<HeldOutErrors> errors;
  FitContexts contexts;
  Chooser(const Scene& s, const SceneMaterial& m) : scene(s), source(open_source(m.source)), pairs(held_out_pairs(s, m, *source)) {
    errors = std::make_unique<HeldOutErrors>(pairs, s.order_max, m.metric);
  }
  MaterialCandidate operator()(const SceneMaterial& m) {
    return choose_representation(MaterialProblem{scene, m, *source, errors.get(), contexts, [](const std::string&) {}});
  }
};

// A target no order up to 4 reaches, a budget of 300 bytes (15 isotropic coefficients of 20 bytes): the
// candidate kept is within the budget, says it missed the target, and no spectrum the search could store
// whole within the budget (any order's truncation of each level's top fit, as fitted or isotropic) has a
// lower error.
TEST(Budget, KeepBestIsTheLowestErrorWithinMaxBytes) {
  const Scene s = small_scene();
  const SceneMaterial m = glossy(1e-6, 300, OnMiss::KeepBest);
  Chooser choose(s, m);
  const MaterialCandidate c = choose(m);
  const HeldOutErrors& errors = *choose.errors;
  const BrdfSource* src = choose.source.get();
  FitContexts& contexts = choose.contexts;
  EXPECT_FALSE(c.target_met);
  EXPECT_LE(c.bytes, m.max_bytes);
  EXPECT_GT(c.error.l2, m.target);
  EXPECT_EQ(errors(c.record.spectrum.channels, c.record.spectrum.order).l2, c.error.l2);  // the error is the record's
  int compared = 0;
  for (const int level : s.levels) {
    FitRequest r;
    r.level = level;
    r.order = s.order_max;
    r.grid_kind = GridKind::EqualArea;
    r.sampling = s.sampling;
    r.order = std::min(s.order_max, contexts.supported_order(r));
    if (r.order < 0) continue;
    const Spectrum top = fit_source(*src, r, contexts).spectrum;
    for (int n = 0; n <= r.order; ++n) {
      Spectrum t = top;
      t.channels = truncate_channels(top.channels, n);
      t.order = n;
      Spectrum iso = t;
      for (auto& ch : iso.channels) ch = isotropic_part(ch, n);
      iso.isotropic = true;
      for (const Spectrum* x : {&t, &iso}) {
        const int count = x->isotropic ? isotropic_mode_count(n) : static_cast<int>(helmholtz_mode_count(n));
        if (modes_bytes(*x, count) > m.max_bytes) continue;
        ++compared;
        EXPECT_LE(c.error.l2, errors(x->channels, n).l2) << "level " << level << " order " << n << (x == &iso ? " isotropic" : "");
      }
    }
  }
  EXPECT_GT(compared, 2);
}

// A Phong lobe the modes of order <= 4 meet at 0.2 (as in test_bank_pieces' pruning test).
const char* kPhong = "model:0.5*lambert+0.5*phong:n=3";

// A target met without a budget is refused within a budget too small for it: "fail" names the lowest error
// within the budget, "keep-best" keeps it.
TEST(Budget, FailNamesTheLowestErrorWithinTheBudgetAndKeepBestKeepsIt) {
  const Scene s = small_scene();
  const SceneMaterial free = glossy(0.2, -1, OnMiss::Fail, kPhong);
  Chooser choose(s, free);
  const MaterialCandidate unbounded = choose(free);
  ASSERT_TRUE(unbounded.target_met);
  ASSERT_GT(unbounded.bytes, 20);
  const SceneMaterial tight = glossy(0.2, unbounded.bytes - 1, OnMiss::Fail, kPhong);
  try {
    choose(tight);
    FAIL() << "no error";
  } catch (const UnsupportedError& e) {
    EXPECT_NE(std::string(e.what()).find("the lowest error within max_bytes"), std::string::npos) << e.what();
  }
  const SceneMaterial keep = glossy(0.2, unbounded.bytes - 1, OnMiss::KeepBest, kPhong);
  const MaterialCandidate kept = choose(keep);
  EXPECT_LE(kept.bytes, keep.max_bytes);
  EXPECT_FALSE(kept.target_met);
  EXPECT_GT(kept.error.l2, keep.target);
}

// Not one coefficient fits: the material fails even with keep-best (nothing to keep).
TEST(Budget, ABudgetBelowOneCoefficientFails) {
  const Scene s = small_scene();
  const SceneMaterial m = glossy(1e-6, 10, OnMiss::KeepBest);
  Chooser choose(s, m);
  EXPECT_THROW(choose(m), UnsupportedError);
}

}  // namespace
}  // namespace icobrdf
