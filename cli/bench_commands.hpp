#pragma once
// Registry of the `icobrdf bench` family, so each benchmark lives in its own cli/bench_<name>.cpp:
// BenchRegistrar adds a subcommand of `bench` (project, sweep, ...), in name order by cli/cmd_bench.cpp;
//     static const icobrdf::cli::BenchRegistrar reg("name", [](CLI::App& bench) { bench.add_subcommand(...); });
// The measurements themselves live in lab/.
#include <CLI/CLI.hpp>

#include <functional>
#include <map>
#include <string>

namespace icobrdf::cli {

using BenchAdder = std::function<void(CLI::App& bench)>;

inline std::map<std::string, BenchAdder>& bench_registry() {
  static std::map<std::string, BenchAdder> registry;
  return registry;
}

struct BenchRegistrar {
  BenchRegistrar(const std::string& name, BenchAdder adder) { bench_registry()[name] = std::move(adder); }
};

}  // namespace icobrdf::cli
