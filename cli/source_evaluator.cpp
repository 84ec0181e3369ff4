#include "cli/source_evaluator.hpp"

#include <map>
#include <memory>

#include "core/error.hpp"
#include "core/model_spec.hpp"

namespace icobrdf::cli {

namespace {

std::map<std::string, SourceOpener>& source_kinds() {
  static std::map<std::string, SourceOpener> kinds;
  return kinds;
}

std::optional<PairEvaluator> open_model_source(const std::string& source) {
  if (!is_model_source(source)) return std::nullopt;
  std::shared_ptr<const BrdfModel> model = parse_model_source(source);
  PairEvaluator e;
  e.description = std::string(kModelSourcePrefix) + model->spec();
  e.columns = channel_column_names(model->channels());
  for (const auto& part : model->delta_parts())
    e.notes.push_back(std::string("values are the regular part only; the ") +
                      (part.kind == DeltaPart::Mirror ? "mirror" : "retroreflector") + " delta part of weight " +
                      format_parameter(part.weight) + " is not representable pointwise");
  e.eval = [model](const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) {
    model->eval(wi, wr, out);
  };
  return e;
}

const SourceKindRegistrar kModelKind("model", open_model_source);

}  // namespace

SourceKindRegistrar::SourceKindRegistrar(const std::string& kind, SourceOpener opener) {
  source_kinds()[kind] = std::move(opener);
}

PairEvaluator open_pair_evaluator(const std::string& source) {
  for (const auto& [kind, opener] : source_kinds())
    if (auto e = opener(source)) return std::move(*e);
  std::string kinds;
  for (const auto& [kind, opener] : source_kinds()) kinds += (kinds.empty() ? "" : ", ") + kind;
  throw ArgumentError("SOURCE '" + source + "' is of no known kind (" + kinds +
                      "); expected model:NAME[:key=value,...] (see icobrdf models)");
}

std::vector<std::string> channel_column_names(int channels) {
  if (channels == 1) return {"f"};
  if (channels == 3) return {"f_r", "f_g", "f_b"};
  std::vector<std::string> names;
  for (int c = 0; c < channels; ++c) names.push_back("f_" + std::to_string(c));
  return names;
}

}  // namespace icobrdf::cli
