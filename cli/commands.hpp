#pragma once
// Subcommand registry. Each subcommand lives in its own cli/cmd_<name>.cpp and registers itself with
//   static const icobrdf::cli::CommandRegistrar reg("name", [](CLI::App& app) { ... add_subcommand ... });
// main() adds every registered command to the root app in name order. A command's callback throws
// icobrdf errors (icobrdf/core/support/error.hpp); main() turns them into one-line messages and exit codes.
#include <CLI/CLI.hpp>

#include <functional>
#include <map>
#include <string>

namespace icobrdf::cli {

using CommandAdder = std::function<void(CLI::App&)>;

inline std::map<std::string, CommandAdder>& command_registry() {
  static std::map<std::string, CommandAdder> registry;
  return registry;
}

struct CommandRegistrar {
  CommandRegistrar(const std::string& name, CommandAdder adder) { command_registry()[name] = std::move(adder); }
};

}  // namespace icobrdf::cli
