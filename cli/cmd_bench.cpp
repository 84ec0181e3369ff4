// icobrdf bench: the family of speed measurements. Each subcommand lives in its own cli/bench_<name>.cpp
// and registers itself (cli/bench_commands.hpp); this file adds them under `bench` in name order.
#include "cli/bench_commands.hpp"
#include "cli/commands.hpp"

namespace icobrdf::cli {
namespace {

void add_bench_command(CLI::App& app) {
  auto* bench = app.add_subcommand("bench", "Measure the engine's speed (and error) against the machine's limit and baselines");
  bench->require_subcommand(1);
  for (auto& [name, adder] : bench_registry()) adder(*bench);
}

const CommandRegistrar kCmdBenchRegistrar("bench", add_bench_command);

}  // namespace
}  // namespace icobrdf::cli
