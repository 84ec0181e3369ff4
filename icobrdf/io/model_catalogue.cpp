#include "icobrdf/io/model_catalogue.hpp"

#include <string>

namespace icobrdf {

nlohmann::json model_parameter_json(const ModelParameter& p) {
  nlohmann::json j;
  j["name"] = p.name;
  if (p.choices.empty()) {
    j["default"] = p.default_value;
    j["min"] = p.min;
    j["max"] = p.max;
    j["unit"] = p.unit;
  } else {
    j["default"] = p.choices.at(static_cast<std::size_t>(p.default_value));
    j["choices"] = p.choices;
  }
  j["meaning"] = p.meaning;
  return j;
}

nlohmann::json model_catalogue_json() {
  nlohmann::json all = nlohmann::json::array();
  for (const auto& info : model_registry()) {
    nlohmann::json m;
    m["name"] = info.name;
    m["summary"] = info.summary;
    m["canonical"] = std::string(kModelSourcePrefix) + parse_model(info.name)->spec();
    m["physical"] = info.physical;
    m["physical_condition"] = info.physical_condition;
    m["delta"] = info.delta;
    m["parameters"] = nlohmann::json::array();
    for (const auto& p : info.parameters) m["parameters"].push_back(model_parameter_json(p));
    all.push_back(m);
  }
  return all;
}

}  // namespace icobrdf
