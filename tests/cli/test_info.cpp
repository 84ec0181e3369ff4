#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/cli/cli_runner.hpp"

using icobrdf::test::run_cli;

TEST(CliInfo, JsonNamesVersionAndLibraries) {
  const auto r = run_cli({"info", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("version").get<std::string>(), ICOBRDF_VERSION_EXPECTED);
  for (const char* key : {"build_type", "eigen", "openmesh", "hdf5", "cli11", "fmt"})
    EXPECT_FALSE(j.at(key).get<std::string>().empty()) << key;
}

TEST(CliInfo, UnknownSubcommandIsAUsageError) {
  const auto r = run_cli({"no-such-command"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_FALSE(r.err.empty());
}

TEST(CliInfo, HelpExitsZero) {
  const auto r = run_cli({"--help"});
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("info"), std::string::npos);
}
