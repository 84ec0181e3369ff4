#pragma once
// The analytic BRDF models (icobrdf/core/models/model_registry.hpp) as `icobrdf models --json` lists them.
#include <nlohmann/json.hpp>

#include "icobrdf/core/models/model_registry.hpp"

namespace icobrdf {

// One parameter: name, meaning, and either default, min, max and unit (numbers, angles in degrees) or default
// and choices (a named choice).
nlohmann::json model_parameter_json(const ModelParameter& p);

// Per model, in the registry's order: name, summary, canonical (its SOURCE text with every default,
// "model:..."), physical (albedo <= 1 for every accepted parameter set), physical_condition, delta, parameters.
nlohmann::json model_catalogue_json();

}  // namespace icobrdf
