#include "icobrdf/pipeline/source_model.hpp"

#include <sys/stat.h>

#include "icobrdf/core/models/function_model.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/brdf_source.hpp"

namespace icobrdf {

std::shared_ptr<const BrdfModel> model_of_source(const std::string& text, std::string* label, std::vector<std::string>* channel_names) {
  if (channel_names) channel_names->clear();
  struct stat st{};
  const std::string path = split_material_ref(text).path;
  if (!is_model_source(text) && ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode)) {
    std::shared_ptr<const BrdfSource> src = open_source(text);
    *label = src->spec();
    if (channel_names) *channel_names = src->channel_names();
    return std::make_shared<FunctionModel>(
        src->channels(), [src](const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) { out = src->eval(wi, wr); },
        src->spec(), false, false);
  }
  std::shared_ptr<const BrdfModel> model = parse_model_source(text.rfind("model:", 0) == 0 ? text : "model:" + text);
  *label = "model:" + model->spec();
  return model;
}

}  // namespace icobrdf
