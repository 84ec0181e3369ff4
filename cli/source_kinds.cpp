// Every SOURCE kind that io/brdf_source.hpp opens (spectrum and bank files, MERL tables, coefficient files,
// ...) as a pair evaluator for `icobrdf eval` (cli/source_evaluator.hpp). Models keep their own opener.
#include <memory>

#include "cli/source_evaluator.hpp"
#include "core/model_spec.hpp"
#include "io/brdf_source.hpp"

namespace icobrdf::cli {
namespace {

std::optional<PairEvaluator> open_file_source(const std::string& source) {
  if (is_model_source(source)) return std::nullopt;
  std::shared_ptr<const BrdfSource> src = open_source(source);
  PairEvaluator e;
  e.description = src->spec();
  e.columns = channel_column_names(src->channels());
  e.eval = [src](const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) { out = src->eval(wi, wr); };
  return e;
}

const SourceKindRegistrar kFileKind("file", open_file_source);

}  // namespace
}  // namespace icobrdf::cli
