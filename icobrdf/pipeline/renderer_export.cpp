#include "icobrdf/pipeline/renderer_export.hpp"

#include <fmt/core.h>
#include <sys/stat.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <memory>

#include "icobrdf/core/fit/half_angle_fit.hpp"
#include "icobrdf/core/models/function_model.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/scramble.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/merl.hpp"
#include "icobrdf/io/rgl_bsdf.hpp"
#include "icobrdf/pipeline/source_model.hpp"

namespace icobrdf {
// Helpers in a namespace of their own: the library compiles in unity batches.
namespace renderer_export_detail {
namespace {

Eigen::MatrixXd values(const BrdfModel& model, const RowMatrix3d& wi, const RowMatrix3d& wr) {
  Eigen::MatrixXd out(wi.rows(), model.channels());
  model.eval(wi, wr, out);
  return out;
}

// |cos cos (f_file - f_source)| / |cos cos f_source| over pairs and channels; a 1-channel source against every
// channel of the file.
double cosine_l2(const Eigen::MatrixXd& file, const Eigen::MatrixXd& source, const RowMatrix3d& wi, const RowMatrix3d& wr) {
  double num = 0, den = 0;
  for (Eigen::Index r = 0; r < file.rows(); ++r) {
    const double w = wi(r, 2) * wr(r, 2);
    for (Eigen::Index c = 0; c < file.cols(); ++c) {
      const double s = source(r, source.cols() == 1 ? 0 : c);
      num += w * w * (file(r, c) - s) * (file(r, c) - s);
      den += w * w * s * s;
    }
  }
  return den > 0 ? std::sqrt(num / den) : (num > 0 ? INFINITY : 0.0);
}

void check_exportable(const BrdfModel& model, const BrdfSource& source, const std::string& format) {
  if (source.has_delta() || !model.delta_parts().empty())
    throw ArgumentError("export --format " + format + ": " + source.spec() +
                        " has a delta part (ideal mirror or retroreflector), which a tabulated file cannot hold");
  if (model.channels() != 1 && model.channels() != 3)
    throw ArgumentError("export --format " + format + ": " + source.spec() + " has " + std::to_string(model.channels()) +
                        " channels, expected 1 or 3 (R, G, B)");
  if (model.is_isotropic() && is_model_source(source.spec())) return;
  RowMatrix3d wi, wr;
  uniform_pairs(kIsotropyCheckPairs, fnv1a64("isotropy|" + source.spec()), wi, wr);
  const Eigen::MatrixXd f = values(model, wi, wr);
  for (const double angle : {2.0, 4.1}) {
    Eigen::Matrix3d turn = Eigen::Matrix3d::Identity();
    turn.topLeftCorner<2, 2>() << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
    const RowMatrix3d ti = wi * turn.transpose(), tr = wr * turn.transpose();
    const double change = (values(model, ti, tr) - f).norm() / std::max(f.norm(), 1e-300);
    if (!(change <= kExportIsotropyTolerance))
      throw ArgumentError(fmt::format("export --format {}: {} is anisotropic (a turn of {} rad about the normal changes its values by {:.3g} "
                                      "relative L2, expected <= {:g}); the {} format holds isotropic materials only",
                                      format, source.spec(), angle, change, kExportIsotropyTolerance, format));
  }
}

// The source with negative values set to 0 (MERL stores -1 for missing samples), counting them.
std::shared_ptr<const BrdfModel> nonnegative(std::shared_ptr<const BrdfModel> model, std::shared_ptr<std::atomic<long long>> count) {
  const int nc = model->channels();
  const std::string spec = model->spec();
  return std::make_shared<FunctionModel>(
      nc,
      [model = std::move(model), count = std::move(count)](const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) {
        model->eval(wi, wr, out);
        long long n = 0;
        for (Eigen::Index r = 0; r < out.rows(); ++r)
          for (Eigen::Index c = 0; c < out.cols(); ++c)
            if (out(r, c) < 0) {
              out(r, c) = 0;
              ++n;
            }
        *count += n;
      },
      spec, true, true);
}

void merl_export(RendererExport& e, const std::shared_ptr<const BrdfModel>& model) {
  auto count = std::make_shared<std::atomic<long long>>(0);
  const std::shared_ptr<const BrdfModel> clamped = nonnegative(model, count);
  write_merl(e.output, *clamped);
  e.negatives_zeroed = count->load();
  const auto table = std::make_shared<const MerlTable>(read_merl(e.output));
  // Nodes spread over the table (every k-th bin), both directions above the horizon.
  const std::int64_t step = kMerlSamplesPerChannel / kMerlNodesChecked;
  RowMatrix3d wi(kMerlNodesChecked, 3), wr(kMerlNodesChecked, 3);
  Eigen::MatrixXd stored(kMerlNodesChecked, 3);
  Eigen::Index rows = 0;
  for (std::int64_t flat = 0; flat < kMerlSamplesPerChannel && rows < kMerlNodesChecked; flat += step) {
    const MerlBin bin{static_cast<int>(flat / (kMerlPhiDiffRes * kMerlThetaDiffRes)),
                      static_cast<int>(flat / kMerlPhiDiffRes % kMerlThetaDiffRes), static_cast<int>(flat % kMerlPhiDiffRes)};
    Eigen::Vector3d a, b;
    directions_from_half_diff(merl_node(bin), a, b);
    if (!(a.z() > 0 && b.z() > 0)) continue;
    wi.row(rows) = a.transpose();
    wr.row(rows) = b.transpose();
    for (int c = 0; c < 3; ++c) stored(rows, c) = table->at(c, bin);
    ++rows;
  }
  const RowMatrix3d wi_n = wi.topRows(rows), wr_n = wr.topRows(rows);
  const Eigen::MatrixXd expected = values(*clamped, wi_n, wr_n);
  double worst = 0, peak = 0;
  for (Eigen::Index r = 0; r < rows; ++r)
    for (int c = 0; c < 3; ++c) {
      const double s = expected(r, expected.cols() == 1 ? 0 : c);
      worst = std::max(worst, std::abs(stored(r, c) - s));
      peak = std::max(peak, std::abs(s));
    }
  e.node_max_rel = peak > 0 ? worst / peak : worst;
  RowMatrix3d pi, pr;
  uniform_pairs(kAgreementPairs, fnv1a64("agreement|" + e.source), pi, pr);
  e.cosine_l2 = cosine_l2(values(MerlModel(table), pi, pr), values(*clamped, pi, pr), pi, pr);
}

void rgl_export(RendererExport& e, const std::shared_ptr<const BrdfModel>& model, const RglExportOptions& options) {
  RglExportOptions o = options;
  if (o.description.empty()) o.description = "icobrdf export of " + e.source;
  e.rgl = write_rgl_export(e.output, *model, o);
  e.bytes = e.rgl.bytes;
  const RglModel back(std::make_shared<const RglBsdf>(read_rgl_bsdf(e.output)), {0, 1, 2}, e.output);
  RowMatrix3d wi, wr;
  uniform_pairs(kAgreementPairs, fnv1a64("agreement|" + e.source), wi, wr);
  e.cosine_l2 = cosine_l2(values(back, wi, wr), values(*model, wi, wr), wi, wr);
}

}  // namespace

RendererExport export_file(const std::string& source_text, const std::string& format, const std::string& output,
                           const RglExportOptions& rgl_options) {
  if (format != "rgl" && format != "merl") throw ArgumentError("--format: expected 'scatmech', 'rgl' or 'merl', found '" + format + "'");
  const std::shared_ptr<const BrdfSource> source = open_source(source_text);
  const std::shared_ptr<const BrdfModel> model = model_of_open_source(source);
  check_exportable(*model, *source, format);
  RendererExport e;
  e.source = source->spec();
  e.format = format;
  e.output = output;
  try {
    if (format == "rgl") rgl_export(e, model, rgl_options);
    else merl_export(e, model);
  } catch (const InputError&) {
    std::remove(output.c_str());  // a file this program cannot read back is not left behind
    throw;
  }
  struct stat st{};
  if (::stat(output.c_str(), &st) == 0) e.bytes = st.st_size;
  return e;
}

}  // namespace renderer_export_detail

RendererExport export_for_renderer(const std::string& source, const std::string& format, const std::string& output,
                                   const RglExportOptions& rgl_options) {
  return renderer_export_detail::export_file(source, format, output, rgl_options);
}

nlohmann::json renderer_export_json(const RendererExport& e) {
  nlohmann::json j = {{"source", e.source}, {"format", e.format}, {"output", e.output}, {"bytes", e.bytes}, {"cosine_rel_l2", e.cosine_l2},
                      {"agreement_pairs", kAgreementPairs}};
  if (e.format == "merl") {
    j["node_max_rel"] = e.node_max_rel;
    j["nodes_checked"] = kMerlNodesChecked;
    j["negatives_zeroed"] = e.negatives_zeroed;
  } else {
    j["theta_i_nodes"] = e.rgl.theta_nodes;
    j["value_resolution"] = e.rgl.value_resolution;
    j["vndf_resolution"] = e.rgl.vndf_resolution;
    j["ndf_resolution"] = e.rgl.ndf_resolution;
  }
  return j;
}

std::string renderer_export_text(const RendererExport& e) {
  if (e.format == "merl")
    return fmt::format("{} -> {} (MERL table, 90 x 90 x 180, {} bytes; {} negative values written as 0)\n"
                       "  read back: largest relative difference at {} nodes {:.3g}; cosine-weighted relative L2 at {} pairs {:.4g}\n",
                       e.source, e.output, e.bytes, e.negatives_zeroed, kMerlNodesChecked, e.node_max_rel, kAgreementPairs, e.cosine_l2);
  return fmt::format("{} -> {} (RGL tensor file, rgb, {} incident elevations, values {}x{}, vndf {}x{}, ndf {}; {} bytes)\n"
                     "  read back: cosine-weighted relative L2 at {} pairs {:.4g}\n",
                     e.source, e.output, e.rgl.theta_nodes, e.rgl.value_resolution, e.rgl.value_resolution, e.rgl.vndf_resolution,
                     e.rgl.vndf_resolution, e.rgl.ndf_resolution, e.bytes, kAgreementPairs, e.cosine_l2);
}

}  // namespace icobrdf
