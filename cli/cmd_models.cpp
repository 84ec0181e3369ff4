// icobrdf models: the analytic BRDF models a SOURCE "model:NAME[:key=value,...]" can name, with their
// parameters (default, accepted range or choices, unit, meaning) and energy conservation.
//   icobrdf models [--json]
// JSON: {"models": [{"name", "summary", "canonical" (the default spec), "physical", "physical_condition",
//   "delta", "parameters": [{"name", "default", "min", "max", "unit", "meaning"} or, for choices,
//   {"name", "default", "choices", "meaning"}]}]}. Angles are in degrees. docs/models.md has the formulas.
#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <iostream>
#include <memory>

#include "cli/commands.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/io/model_catalogue.hpp"

namespace icobrdf::cli {

namespace {

void run_models(bool json) {
  if (json) {
    std::cout << nlohmann::json{{"models", model_catalogue_json()}}.dump(2) << "\n";
    return;
  }
  std::string text;
  for (const auto& info : model_registry()) {
    const std::string canonical = std::string(kModelSourcePrefix) + parse_model(info.name)->spec();
    text += fmt::format("{}{}\n  {}\n  default: {}\n", text.empty() ? "" : "\n", info.name, info.summary, canonical);
    text += info.physical ? std::string("  energy: albedo <= 1 for every accepted parameter set\n")
                          : fmt::format("  energy: albedo <= 1 only when {}\n", info.physical_condition);
    for (const auto& p : info.parameters) {
      if (p.choices.empty()) {
        text += fmt::format("  {:<9} default {:<10} range [{}, {}]{}  {}\n", p.name, format_parameter(p.default_value),
                            format_parameter(p.min), format_parameter(p.max), p.unit.empty() ? "" : " " + p.unit,
                            p.meaning);
      } else {
        std::string choices;
        for (const auto& c : p.choices) choices += (choices.empty() ? "" : "|") + c;
        text += fmt::format("  {:<9} default {:<10} one of {}  {}\n", p.name,
                            p.choices.at(static_cast<std::size_t>(p.default_value)), choices, p.meaning);
      }
    }
  }
  std::cout << "Analytic BRDF models: SOURCE model:NAME[:key=value,...], sums model:0.8*a+0.2*b; angles in degrees.\n\n"
            << text;
}

void add_models_command(CLI::App& app) {
  auto json = std::make_shared<bool>(false);
  auto* cmd = app.add_subcommand("models", "List the analytic BRDF models with their parameters and defaults");
  cmd->add_flag("--json", *json, "Machine-readable output");
  cmd->callback([json] { run_models(*json); });
}

const CommandRegistrar kCmdModelsRegistrar("models", add_models_command);

}  // namespace
}  // namespace icobrdf::cli
