#include "icobrdf/pipeline/source_model.hpp"

#include <sys/stat.h>

#include "icobrdf/core/models/function_model.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/brdf_source.hpp"

namespace icobrdf {
namespace {

std::shared_ptr<const BrdfModel> values_model(std::shared_ptr<const BrdfSource> src) {
  const std::string spec = src->spec();
  const int channels = src->channels();
  return std::make_shared<FunctionModel>(
      channels, [src = std::move(src)](const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) { out = src->eval(wi, wr); },
      spec, false, false);
}

// A SOURCE named by its kind's prefix (icobrdf/io/measured_sources.hpp): a file, though the text does not
// name one ("curet:abrdf.dat#sample=1" was parsed as a model and refused as "unknown model 'curet'").
bool has_measured_source_prefix(const std::string& text) {
  for (const char* p : {"merl:", "rgl:", "scatmech:", "samples:", "curet:"})
    if (text.rfind(p, 0) == 0) return true;
  return false;
}

}  // namespace

std::shared_ptr<const BrdfModel> model_of_source(const std::string& text, std::string* label, std::vector<std::string>* channel_names) {
  if (channel_names) channel_names->clear();
  struct stat st{};
  const std::string path = split_material_ref(text).path;
  if (!is_model_source(text) && (has_measured_source_prefix(text) || (::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode)))) {
    std::shared_ptr<const BrdfSource> src = open_source(text);
    *label = src->spec();
    if (channel_names) *channel_names = src->channel_names();
    return values_model(src);
  }
  std::shared_ptr<const BrdfModel> model = parse_model_source(text.rfind("model:", 0) == 0 ? text : "model:" + text);
  *label = "model:" + model->spec();
  return model;
}

std::shared_ptr<const BrdfModel> model_of_open_source(std::shared_ptr<const BrdfSource> source) {
  if (is_model_source(source->spec())) return parse_model_source(source->spec());
  return values_model(std::move(source));
}

}  // namespace icobrdf
