#pragma once
// Each subcommand lives in its own cmd_<name>.cpp and registers itself on the root app here.
// A command's callback throws icobrdf errors (core/error.hpp); main() turns them into one-line messages
// and exit codes.
#include <CLI/CLI.hpp>

namespace icobrdf::cli {
void add_info_command(CLI::App& app);
}  // namespace icobrdf::cli
