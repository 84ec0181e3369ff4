// Held-out splits of measured samples (icobrdf/pipeline/held_out.hpp held_out_split): the held-out samples are
// samples of the source, the training source no longer holds them, and the split is reproducible and seeded
// by the material's name. End-to-end builds are in tests/cli/test_bank_measured.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/measured_sources.hpp"
#include "icobrdf/io/merl.hpp"
#include "icobrdf/pipeline/held_out.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

struct Scratch {
  std::string path;
  Scratch() {
    char tmpl[] = "/tmp/icobrdf-split-XXXXXX";
    path = ::mkdtemp(tmpl);
  }
  ~Scratch() { std::system(("rm -rf '" + path + "'").c_str()); }
  std::string file(const std::string& name) const { return path + "/" + name; }
};

SceneMaterial material(const std::string& name, const std::string& source) {
  SceneMaterial m;
  m.name = name;
  m.source = source;
  return m;
}

// 60 samples, f = 0.01 * (k + 1) at sample k (distinct values name the sample); incidence 2k + 1 degrees.
std::string write_samples(const Scratch& d) {
  const std::string p = d.file("s.csv");
  std::ofstream out(p);
  out << "theta_i,phi_i,theta_r,phi_r,value\n";
  for (int k = 0; k < 60; ++k) out << 2 * k / 3.0 + 1 << ",0," << 40 << "," << 3 * k << "," << 0.01 * (k + 1) << "\n";
  return p;
}

TEST(HeldOutSplit, CsvSamplesSplitOneInFiveReproduciblyBySeed) {
  Scratch d;
  const auto src = open_source(write_samples(d));
  Scene s;
  const SceneMaterial m = material("a", src->spec());
  const HeldOutSplit h = held_out_split(s, m, *src);
  ASSERT_TRUE(h.training);
  ASSERT_EQ(h.pairs.wi.rows(), 60 / kHeldOutShare);
  const BrdfSamples* train = samples_of(*h.training);
  ASSERT_NE(train, nullptr);
  EXPECT_EQ(train->wi.rows(), 60 - 60 / kHeldOutShare);
  // Held-out and training values are disjoint and together all the samples.
  std::set<long> held, all;
  for (Eigen::Index k = 0; k < h.pairs.f.rows(); ++k) held.insert(std::lround(h.pairs.f(k, 0) * 100));
  for (Eigen::Index k = 0; k < train->values.rows(); ++k) {
    const long v = std::lround(train->values(k, 0) * 100);
    EXPECT_EQ(held.count(v), 0u) << "sample " << v << " both held out and fitted";
    all.insert(v);
  }
  all.insert(held.begin(), held.end());
  EXPECT_EQ(all.size(), 60u);
  // Reproducible; another name draws another split.
  EXPECT_EQ(held_out_split(s, m, *src).pairs.f, h.pairs.f);
  EXPECT_NE(held_out_split(s, material("b", src->spec()), *src).pairs.f, h.pairs.f);
  // The scene's holdout_pairs bounds the count; the incidence range restricts the held-out samples only.
  s.holdout_pairs = 3;
  EXPECT_EQ(held_out_split(s, m, *src).pairs.wi.rows(), 3);
  SceneMaterial narrow = m;
  narrow.incidence_max = 10.0;  // samples k <= 13 (incidence 2k/3 + 1 <= 10)
  s.holdout_pairs = 4096;
  const HeldOutSplit hn = held_out_split(s, narrow, *src);
  for (Eigen::Index k = 0; k < hn.pairs.wi.rows(); ++k) EXPECT_GE(hn.pairs.wi(k, 2), std::cos(10.0 * M_PI / 180) - 1e-15);
  EXPECT_EQ(samples_of(*hn.training)->wi.rows(), 60 - hn.pairs.wi.rows());
}

// A file in scan order is held out evenly, not by runs of neighbouring samples: in every run of 100
// consecutive samples of 2,000, one in five held out gives 20 on average, with a standard deviation of 4 (binomial,
// 100 x 0.2 x 0.8); a split by runs gives 0 or 100.
TEST(HeldOutSplit, HeldOutSamplesAreSpreadOverTheFile) {
  constexpr int kSamples = 2000, kRun = 100, kLeast = 20 - 5 * 4, kMost = 20 + 5 * 4;  // five standard deviations
  Scratch d;
  {
    std::ofstream out(d.file("scan.csv"));
    out << "theta_i,phi_i,theta_r,phi_r,value\n";
    for (int k = 0; k < kSamples; ++k) out << 1 + (k / 40) * 1.5 << "," << 0 << "," << 1 + (k % 40) * 2 << ",180," << k + 1 << "\n";
  }
  const auto src = open_source(d.file("scan.csv"));
  const HeldOutSplit h = held_out_split(Scene{}, material("a", src->spec()), *src);
  ASSERT_EQ(h.pairs.f.rows(), kSamples / kHeldOutShare);
  std::vector<int> per_run(kSamples / kRun, 0);
  for (Eigen::Index k = 0; k < h.pairs.f.rows(); ++k) ++per_run[static_cast<size_t>((std::lround(h.pairs.f(k, 0)) - 1) / kRun)];
  for (size_t r = 0; r < per_run.size(); ++r) {
    EXPECT_GE(per_run[r], kLeast) << "samples " << r * kRun << ".." << (r + 1) * kRun - 1;
    EXPECT_LE(per_run[r], kMost) << "samples " << r * kRun << ".." << (r + 1) * kRun - 1;
  }
}

TEST(HeldOutSplit, MerlBinsHeldOutAreMissingFromTheTrainingTable) {
  Scratch d;
  const std::string table = d.file("t.binary");
  write_merl(table, *parse_model("lambert:albedo=0.5"));
  const auto src = open_source("merl:" + table);
  Scene s;
  s.holdout_pairs = 256;
  const HeldOutSplit h = held_out_split(s, material("a", src->spec()), *src);
  ASSERT_TRUE(h.training);
  ASSERT_EQ(h.pairs.wi.rows(), 256);
  // The source has a value at every held-out pair, the training table none: each bin drawn is missing (all
  // three channels), and no other bin.
  const Eigen::MatrixXd full = src->eval(h.pairs.wi, h.pairs.wr), left = h.training->eval(h.pairs.wi, h.pairs.wr);
  EXPECT_TRUE(full.allFinite());
  for (Eigen::Index k = 0; k < left.size(); ++k) EXPECT_TRUE(std::isnan(left.data()[k])) << "pair " << k % left.rows();
  std::set<std::int64_t> bins;
  const MerlTable* t = merl_table_of(*h.training);
  ASSERT_NE(t, nullptr);
  for (std::int64_t b = 0; b < kMerlSamplesPerChannel; ++b)
    if (std::isnan(t->f[static_cast<size_t>(b)])) bins.insert(b);
  EXPECT_EQ(t->missing_total(), 3 * static_cast<std::int64_t>(bins.size()));
  EXPECT_LE(bins.size(), 256u);
  EXPECT_EQ(merl_missing_samples(*src), 0);  // the source itself is untouched
}

}  // namespace ICOBRDF_UNITY_ID
}  // namespace icobrdf
