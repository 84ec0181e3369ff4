#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <set>

#include "tests/cli/cli_runner.hpp"

using icobrdf::test::run_cli;

TEST(CliModels, JsonListsEveryModelWithParametersRangesAndDefaults) {
  const auto r = run_cli({"models", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  std::set<std::string> names;
  for (const auto& m : j.at("models")) {
    names.insert(m.at("name").get<std::string>());
    EXPECT_FALSE(m.at("summary").get<std::string>().empty());
    EXPECT_EQ(m.at("canonical").get<std::string>().rfind("model:" + m.at("name").get<std::string>(), 0), 0u);
    EXPECT_TRUE(m.at("physical").is_boolean());
    for (const auto& p : m.at("parameters")) {
      EXPECT_FALSE(p.at("meaning").get<std::string>().empty());
      if (p.contains("choices")) {
        const auto choices = p.at("choices").get<std::vector<std::string>>();
        EXPECT_NE(std::find(choices.begin(), choices.end(), p.at("default").get<std::string>()), choices.end());
      } else {
        EXPECT_LE(p.at("min").get<double>(), p.at("default").get<double>());
        EXPECT_LE(p.at("default").get<double>(), p.at("max").get<double>());
      }
    }
  }
  for (const char* n : {"lambert", "minnaert", "phong", "blinn-phong", "ggx", "beckmann", "ggx-aniso", "oren-nayar",
                        "lafortune", "hapke", "mirror", "retroreflector"})
    EXPECT_TRUE(names.count(n)) << n;
  // ggx: alpha with its default and range; Fresnel choices.
  for (const auto& m : j.at("models")) {
    if (m.at("name") != "ggx") continue;
    const auto& alpha = m.at("parameters").at(0);
    EXPECT_EQ(alpha.at("name"), "alpha");
    EXPECT_EQ(alpha.at("default").get<double>(), 0.3);
    EXPECT_EQ(alpha.at("min").get<double>(), 0.001);
    EXPECT_EQ(m.at("parameters").at(1).at("choices").size(), 3u);
  }
}

TEST(CliModels, TextNamesModelsAndDefaults) {
  const auto r = run_cli({"models"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* s : {"lambert", "oren-nayar", "default: model:ggx:alpha=0.3", "one of schlick|dielectric|none",
                        "only when k >= 1"})
    EXPECT_NE(r.out.find(s), std::string::npos) << s;
}
