// icobrdf info: version, build type and the versions of the libraries found at build time.
#include <Eigen/Core>
#include <OpenMesh/Core/System/config.h>
#include <hdf5.h>
#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <iostream>

#include "cli/commands.hpp"

namespace icobrdf::cli {

namespace {

void add_info_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("info", "Print version, build type and library versions");
  auto json_flag = std::make_shared<bool>(false);
  cmd->add_flag("--json", *json_flag, "Machine-readable output");
  cmd->callback([json_flag] {
    unsigned h5maj = 0, h5min = 0, h5rel = 0;
    H5get_libversion(&h5maj, &h5min, &h5rel);
    nlohmann::json j;
    j["version"] = ICOBRDF_VERSION;
    j["build_type"] = ICOBRDF_BUILD_TYPE;
    j["compiler"] = fmt::format("{} {}.{}.{}", "gcc", __GNUC__, __GNUC_MINOR__, __GNUC_PATCHLEVEL__);
    j["eigen"] = fmt::format("{}.{}.{}", EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION);
    j["eigen_simd"] = Eigen::SimdInstructionSetsInUse();
    j["openmesh"] = fmt::format("{}.{}", (OM_VERSION >> 16) & 0xff, (OM_VERSION >> 8) & 0xff);
    j["hdf5"] = fmt::format("{}.{}.{}", h5maj, h5min, h5rel);
    j["cli11"] = CLI11_VERSION;
    j["fmt"] = fmt::format("{}.{}.{}", FMT_VERSION / 10000, FMT_VERSION / 100 % 100, FMT_VERSION % 100);
    if (*json_flag) {
      std::cout << j.dump(2) << "\n";
      return;
    }
    for (auto it = j.begin(); it != j.end(); ++it)
      std::cout << fmt::format("{:<11} {}\n", it.key(), it.value().get<std::string>());
  });
}

const CommandRegistrar kCmdInfoRegistrar("info", add_info_command);

}  // namespace
}  // namespace icobrdf::cli
