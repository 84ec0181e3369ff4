// SOURCE strings: registry, parsing, canonical specs, sums and weights, and the errors for bad specs.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "tests/core/brdf_quadrature.hpp"
#include "tests/support/unity_id.hpp"

using namespace icobrdf;

namespace ICOBRDF_UNITY_ID {
// parse(spec()) must reproduce the parameters exactly (shortest round-trip formatting): bitwise equal.
constexpr double kExact = 0.0;
// Sums add the terms' values in a different order than the test: rounding only.
constexpr double kSumTol = 1e-13;

Eigen::VectorXd values(const BrdfModel& m, const test::PairSet& p) {
  Eigen::MatrixXd out(p.wi.rows(), m.channels());
  m.eval(p.wi, p.wr, out);
  return out.col(0);
}

std::string error_of(const std::string& spec) {
  try {
    parse_model(spec);
  } catch (const ArgumentError& e) {
    return e.what();
  }
  return "";
}

TEST(ModelSpec, RegistryListsTheIssueNamesWithSaneParameters) {
  for (const char* name : {"lambert", "minnaert", "phong", "blinn-phong", "ggx", "beckmann", "ggx-aniso", "oren-nayar",
                           "lafortune", "hapke", "mirror", "retroreflector"})
    EXPECT_NE(find_model_info(name), nullptr) << name;
  EXPECT_EQ(find_model_info("nope"), nullptr);
  for (const auto& info : model_registry()) {
    EXPECT_FALSE(info.summary.empty()) << info.name;
    EXPECT_EQ(info.physical, info.physical_condition.empty()) << info.name;
    for (const auto& p : info.parameters) {
      EXPECT_LE(p.min, p.default_value) << info.name << "." << p.name;
      EXPECT_LE(p.default_value, p.max) << info.name << "." << p.name;
      EXPECT_FALSE(p.meaning.empty()) << info.name << "." << p.name;
      if (!p.choices.empty()) {
        EXPECT_EQ(p.max, static_cast<double>(p.choices.size() - 1));
      }
    }
  }
}

TEST(ModelSpec, CanonicalSpecRoundTripsForDefaultsAndRandomParameters) {
  const auto pairs = test::test_pairs(300);
  std::mt19937_64 rng(99);
  for (const auto& info : model_registry()) {
    for (int trial = 0; trial < 6; ++trial) {
      std::string spec = info.name;
      for (std::size_t k = 0; k < info.parameters.size() && trial > 0; ++k) {
        const auto& p = info.parameters[k];
        std::string v;
        if (!p.choices.empty()) {
          v = p.choices[rng() % p.choices.size()];
        } else {
          // Random values, with extremes of the range on some trials.
          const double u = std::uniform_real_distribution<double>(0.0, 1.0)(rng);
          const double x = trial == 1 ? p.min : trial == 2 ? p.max : p.min + u * std::min(p.max - p.min, 50.0);
          v = format_parameter(x);
        }
        spec += (k == 0 ? ":" : ",") + p.name + "=" + v;
      }
      std::unique_ptr<BrdfModel> m;
      try {
        m = parse_model(spec);
      } catch (const ArgumentError& e) {  // only the Lafortune overflow guard may refuse in-range values
        EXPECT_NE(std::string(e.what()).find("overflows"), std::string::npos) << e.what();
        continue;
      }
      const std::string canonical = m->spec();
      const auto again = parse_model(canonical);
      EXPECT_EQ(again->spec(), canonical) << spec;
      EXPECT_EQ(canonical.rfind(info.name, 0), 0u) << canonical;
      const Eigen::VectorXd a = values(*m, pairs), b = values(*again, pairs);
      for (Eigen::Index r = 0; r < a.size(); ++r) ASSERT_NEAR(a(r), b(r), kExact) << canonical;
      EXPECT_EQ(m->is_isotropic(), again->is_isotropic());
    }
  }
}

TEST(ModelSpec, CanonicalSpecListsEveryParameterInRegistryOrder) {
  EXPECT_EQ(parse_model("lambert")->spec(), "lambert:albedo=1");
  EXPECT_EQ(parse_model(" ggx : f0 = 0.05 , alpha=0.2 ")->spec(),
            "ggx:alpha=0.2,fresnel=schlick,f0=0.05,ior=1.5,masking=correlated");
  EXPECT_EQ(parse_model("mirror")->spec(), "mirror");
  EXPECT_EQ(parse_model("minnaert:k=1e-5")->spec(), "minnaert:k=0.00001");
  EXPECT_EQ(parse_model("0.8*lambert+0.2*mirror")->spec(), "0.8*lambert:albedo=1+0.2*mirror");
  EXPECT_EQ(format_parameter(0.1), "0.1");
  EXPECT_EQ(format_parameter(20.0), "20");
  EXPECT_EQ(format_parameter(1e-20), "1e-20");
  EXPECT_EQ(std::strtod(format_parameter(M_PI).c_str(), nullptr), M_PI);
}

TEST(ModelSpec, SumsAndWeightsAreLinear) {
  const auto pairs = test::test_pairs(400);
  const auto a = parse_model("lambert:albedo=0.5"), b = parse_model("ggx:alpha=0.2,f0=0.04");
  const auto c = parse_model("hapke:w=0.7");
  const auto sum = parse_model("0.3*lambert:albedo=0.5 + 0.7*ggx:alpha=0.2,f0=0.04+2*hapke:w=0.7");
  const Eigen::VectorXd expected = 0.3 * values(*a, pairs) + 0.7 * values(*b, pairs) + 2.0 * values(*c, pairs);
  const Eigen::VectorXd got = values(*sum, pairs);
  for (Eigen::Index k = 0; k < got.size(); ++k) ASSERT_NEAR(got(k), expected(k), kSumTol * std::max(1.0, expected(k)));
  // A scaling alone.
  const Eigen::VectorXd half = values(*parse_model("0.5*ggx:alpha=0.2,f0=0.04"), pairs);
  for (Eigen::Index k = 0; k < half.size(); ++k) ASSERT_EQ(half(k), 0.5 * values(*b, pairs)(k));
  // Flattening: a sum of sums multiplies the weights.
  std::vector<SumModel::Term> inner = {{0.5, std::shared_ptr<const BrdfModel>(parse_model("lambert"))},
                                       {0.25, std::shared_ptr<const BrdfModel>(parse_model("mirror"))}};
  const SumModel outer({{2.0, std::make_shared<SumModel>(inner)}, {1.0, std::shared_ptr<const BrdfModel>(parse_model("retroreflector"))}});
  EXPECT_EQ(outer.spec(), "lambert:albedo=1+0.5*mirror+retroreflector");
  EXPECT_EQ(outer.terms().size(), 3u);
  // Isotropy of sums: any anisotropic term makes the sum anisotropic.
  EXPECT_TRUE(sum->is_isotropic());
  EXPECT_FALSE(parse_model("lambert+0.1*ggx-aniso")->is_isotropic());
  // '+' after an exponent belongs to the number.
  EXPECT_EQ(parse_model("lambert:albedo=1e+0+mirror")->spec(), "lambert:albedo=1+mirror");
  EXPECT_EQ(parse_model("2.5E+0*lambert:albedo=0.2")->spec(), "2.5*lambert:albedo=0.2");
}

TEST(ModelSpec, DeltaPartsOfSums) {
  const auto m = parse_model("mirror+0.05*lambert");
  auto parts = m->delta_parts();
  ASSERT_EQ(parts.size(), 1u);
  EXPECT_EQ(parts[0].kind, DeltaPart::Mirror);
  EXPECT_EQ(parts[0].weight, 1.0);
  EXPECT_NEAR(m->eval(test::dir_deg(30, 0), test::dir_deg(30, 180)), 0.05 / M_PI, kSumTol);
  parts = parse_model("0.5*mirror+0.25*mirror+0.3*retroreflector+lambert")->delta_parts();
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(parts[0].kind, DeltaPart::Mirror);
  EXPECT_EQ(parts[0].weight, 0.75);
  EXPECT_EQ(parts[1].kind, DeltaPart::Retroreflector);
  EXPECT_EQ(parts[1].weight, 0.3);
  EXPECT_TRUE(parse_model("lambert+ggx")->delta_parts().empty());
}

TEST(ModelSpec, ChannelsBroadcastInSums) {
  // A 3-channel test model: channel c is (c + 1) * lambert.
  struct Rgb final : BrdfModel {
    int channels() const override { return 3; }
    using BrdfModel::eval;
    void eval(const RowMatrix3d& wi, const RowMatrix3d&, Eigen::Ref<Eigen::MatrixXd> out) const override {
      for (Eigen::Index r = 0; r < wi.rows(); ++r) out.row(r) << 1 / M_PI, 2 / M_PI, 3 / M_PI;
    }
    std::string spec() const override { return "rgb"; }
  };
  const SumModel s({{1.0, std::make_shared<Rgb>()}, {0.5, std::shared_ptr<const BrdfModel>(parse_model("lambert"))}});
  EXPECT_EQ(s.channels(), 3);
  RowMatrix3d w(1, 3);
  w << 0, 0, 1;
  Eigen::MatrixXd out(1, 3);
  s.eval(w, w, out);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(out(0, c), (c + 1.5) / M_PI, kSumTol);
}

TEST(ModelSpec, BadSpecsAreOneLineArgumentErrorsNamingTheProblem) {
  struct Case {
    const char* spec;
    std::vector<const char*> mentions;
  };
  for (const auto& c : std::vector<Case>{
           {"ggxx", {"ggxx", "unknown model", "lambert"}},
           {"ggx:alpha=7", {"alpha", "[0.001, 4]", "got 7", "ggx:alpha=7"}},
           {"ggx:alpha=-0.1", {"alpha", "got -0.1"}},
           {"ggx:beta=1", {"unknown parameter 'beta'", "alpha"}},
           {"ggx:alpha=abc", {"alpha", "got 'abc'"}},
           {"ggx:alpha=nan", {"alpha", "'nan'"}},
           {"ggx:alpha=inf", {"alpha", "'inf'"}},
           {"ggx:alpha", {"not key=value"}},
           {"ggx:alpha=0.2,alpha=0.3", {"given twice"}},
           {"ggx:fresnel=exact", {"fresnel", "schlick|dielectric|none", "'exact'"}},
           {"mirror:weight=1", {"unknown parameter 'weight'", "no parameters"}},
           {"lambert+", {"empty term"}},
           {"", {"empty term"}},
           {"-1*lambert", {"weight '-1'"}},
           {"x*lambert", {"weight 'x'"}},
           {"minnaert:k=101", {"k", "[0, 100]", "got 101"}},
           {"lambert:albedo=1.5", {"albedo", "[0, 1]", "1.5"}},
           {"lafortune:cx=10,n=400", {"overflows", "10^400", "<= 300"}},
           // Control bytes of the spec are quoted as \xHH (found by fuzz_model_spec: "la\n\0tro..." gave a
           // message spanning two lines).
           {"la\ntro", {"unknown model", "la\\x0atro"}},
           {"ggx:alpha=0.1\x01", {"alpha", "0.1\\x01"}},
       }) {
    const std::string msg = error_of(c.spec);
    ASSERT_FALSE(msg.empty()) << "no error for '" << c.spec << "'";
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    for (const char* m : c.mentions) EXPECT_NE(msg.find(m), std::string::npos) << "'" << msg << "' lacks '" << m << "'";
  }
}

TEST(ModelSpec, ModelSourcePrefix) {
  EXPECT_TRUE(is_model_source("model:lambert"));
  EXPECT_FALSE(is_model_source("spectrum.h5"));
  EXPECT_EQ(parse_model_source("model:ggx:alpha=0.2,f0=0.04")->spec(),
            "ggx:alpha=0.2,fresnel=schlick,f0=0.04,ior=1.5,masking=correlated");
  EXPECT_THROW(parse_model_source("lambert"), ArgumentError);
}

// Issue #19: a 7,000-term spec with one typo gave a 119 KB message (the whole spec, quoted). The message
// names the failing term and its place, and quotes at most kQuoteLimit characters of anything.
TEST(ModelSpec, TypoInAHugeSpecGivesOneShortLine) {
  constexpr std::size_t kShortLine = 300;  // "one short line": the issue's bound for this message
  std::string spec;
  for (int k = 0; k < 7000; ++k) spec += (k ? "+" : "") + std::string(k == 4321 ? "0.001*lambrt" : "0.001*lambert:albedo=0.5");
  const std::string msg = error_of(spec);
  ASSERT_FALSE(msg.empty());
  EXPECT_LT(msg.size(), kShortLine) << msg.size();
  EXPECT_NE(msg.find("term 4322 of 7000"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'lambrt'"), std::string::npos) << msg;
  // A single huge term (a 1 MB parameter value) is quoted cut, with its length.
  const std::string value(1000000, '9');
  const std::string one = error_of("lambert:albedo=" + value);
  EXPECT_LT(one.size(), 3 * kQuoteLimit + kShortLine) << one.size();  // spec and value, each cut
  EXPECT_NE(one.find("(1000000 characters)"), std::string::npos) << one.substr(0, 400);
}

}  // namespace ICOBRDF_UNITY_ID
