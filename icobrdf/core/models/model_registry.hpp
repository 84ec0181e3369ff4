#pragma once
// SOURCE names of the analytic BRDF models: parsing and the registry of models with their parameters.
//
// Grammar (blanks around tokens are ignored):
//   spec   := term ('+' term)*
//   term   := [weight '*'] name [':' key '=' value (',' key '=' value)*]
// e.g. "ggx:alpha=0.2,f0=0.04", "0.8*lambert+0.2*ggx:alpha=0.1", "mirror+0.05*lambert".
// A '+' directly after an exponent's e/E (as in 1e+5) belongs to the number. Weights are finite and >= 0.
// Missing parameters take their defaults; angles are in degrees. A single term of weight 1 gives the
// model itself, anything else a SumModel. Every error is an ArgumentError naming the spec, the
// parameter, the expected range or choices, and the actual value.
#include <memory>
#include <string>
#include <vector>

#include "icobrdf/core/models/brdf_model.hpp"

namespace icobrdf {

struct ModelParameter {
  std::string name;
  double default_value;  // for a choice parameter: index into `choices`
  double min, max;       // closed range of accepted values (choices: 0 .. choices.size() - 1)
  std::string meaning;
  std::string unit;                  // "" (dimensionless), "deg"
  std::vector<std::string> choices;  // non-empty for a parameter taking one of these names
};

struct ModelInfo {
  std::string name, summary;
  std::vector<ModelParameter> parameters;
  bool physical;                   // directional albedo <= 1 for every parameter set in range
  std::string physical_condition;  // the energy-conserving subset when not `physical` ("k >= 1"), else ""
  bool delta = false;              // has delta parts (mirror, retroreflector)
};

const std::vector<ModelInfo>& model_registry();
// nullptr when unknown.
const ModelInfo* find_model_info(const std::string& name);

std::unique_ptr<BrdfModel> parse_model(const std::string& spec);

// SOURCE strings as the CLI takes them: "model:" followed by a spec.
inline constexpr const char* kModelSourcePrefix = "model:";
bool is_model_source(const std::string& source);
// parse_model of the part after "model:"; ArgumentError when the prefix is missing.
std::unique_ptr<BrdfModel> parse_model_source(const std::string& source);

}  // namespace icobrdf
