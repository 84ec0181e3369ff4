#include "icobrdf/io/brdf_source.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <optional>
#include <vector>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/models/function_model.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/basis/horizon.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/spectrum/spectrum_ops.hpp"
#include "icobrdf/io/measured_sources.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/material_eval.hpp"
#include "icobrdf/io/spectrum_file.hpp"

namespace icobrdf {
namespace {

class ModelSource final : public BrdfSource {
 public:
  explicit ModelSource(std::unique_ptr<BrdfModel> m) : model_(std::move(m)) {}
  std::string spec() const override { return "model:" + model_->spec(); }
  int channels() const override { return model_->channels(); }
  bool has_delta() const override { return !model_->delta_parts().empty(); }
  bool reciprocal_by_construction() const override { return model_->is_reciprocal(); }
  std::vector<std::string> notes() const override {
    std::vector<std::string> out;
    for (const auto& part : model_->delta_parts())
      out.push_back(std::string("values are the regular part only; the ") +
                    (part.kind == DeltaPart::Mirror ? "mirror" : "retroreflector") + " delta part of weight " +
                    format_parameter(part.weight) + " is not representable pointwise");
    return out;
  }
  Eigen::MatrixXd eval(const RowMatrix3d& wi, const RowMatrix3d& wr) const override {
    Eigen::MatrixXd out(wi.rows(), model_->channels());
    model_->eval(wi, wr, out);
    return out;
  }
  Spectrum fit(const ProjectionContext& ctx, const FitOptions& o) const override {
    Spectrum s = fit_model(*model_, ctx, o);
    s.source = spec();
    return s;
  }

 private:
  std::unique_ptr<BrdfModel> model_;
};

// A stored material: modes, and for the representations "half-angle" and "hybrid" a half-angle lobe added
// to them (icobrdf/io/spectrum_file.hpp).
class SpectrumSource final : public BrdfSource {
 public:
  SpectrumSource(Spectrum s, std::optional<HalfAngleFactors> lobe, std::string text)
      : s_(std::move(s)), lobe_(std::move(lobe)), text_(std::move(text)) {}
  std::string spec() const override { return text_; }
  int channels() const override { return s_.channel_count(); }
  std::vector<std::string> channel_names() const override { return s_.channel_names; }
  // The horizon convention of every other source (icobrdf/core/models/brdf_model.hpp): f = 0 where a direction
  // lies below the horizon (z < -kHorizonSlack), a z in [-kHorizonSlack, 0) taken as 0 (the modes are defined
  // on the closed hemisphere only); so consumers that tabulate over every direction pair (a MERL table's bins)
  // take a stored material as they take a model. Non-finite directions still fail in the evaluation.
  Eigen::MatrixXd eval(const RowMatrix3d& wi, const RowMatrix3d& wr) const override {
    const Eigen::Index n = wi.rows();
    bool above = true;
    for (Eigen::Index r = 0; r < n && above; ++r) above = wi(r, 2) >= 0 && wr(r, 2) >= 0;
    if (above) return evaluate_material(s_, lobe_, wi, wr);
    std::vector<Eigen::Index> keep;
    for (Eigen::Index r = 0; r < n; ++r)
      if (!(wi(r, 2) < -kHorizonSlack || wr(r, 2) < -kHorizonSlack)) keep.push_back(r);
    Eigen::MatrixXd out = Eigen::MatrixXd::Zero(n, channels());
    if (keep.empty()) return out;
    const auto m = static_cast<Eigen::Index>(keep.size());
    RowMatrix3d a(m, 3), b(m, 3);
    for (Eigen::Index k = 0; k < m; ++k) {
      a.row(k) = wi.row(keep[static_cast<size_t>(k)]);
      b.row(k) = wr.row(keep[static_cast<size_t>(k)]);
      a(k, 2) = std::max(a(k, 2), 0.0);  // NaN stays NaN
      b(k, 2) = std::max(b(k, 2), 0.0);
    }
    const Eigen::MatrixXd v = evaluate_material(s_, lobe_, a, b);
    for (Eigen::Index k = 0; k < m; ++k) out.row(keep[static_cast<size_t>(k)]) = v.row(k);
    return out;
  }
  // Re-expansion of stored modes at another order is exact in the continuous basis: truncation to a lower
  // order, zero padding to a higher one (no grid is involved). A lobe is projected on the context's grid
  // like a model (its values sampled as the LUT rows).
  Spectrum fit(const ProjectionContext& ctx, const FitOptions& o) const override {
    if (lobe_) {
      const FunctionModel model(
          channels(), [this](const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) { out = eval(wi, wr); },
          text_, s_.isotropic && lobe_->isotropic, true);
      Spectrum s = fit_model(model, ctx, o);
      s.source = text_;
      return s;
    }
    Spectrum s = s_;
    const int m_new = hemisphere_basis_count(o.order), m_old = s_.modes(), k = std::min(m_new, m_old);
    for (auto& c : s.channels) {
      Eigen::MatrixXd r = Eigen::MatrixXd::Zero(m_new, m_new);
      r.topLeftCorner(k, k) = c.topLeftCorner(k, k);
      if (o.isotropic) r = isotropic_part(r, o.order);
      if (o.filter.kind != LowPassFilter::Kind::None) r = filter_coefficients(r, o.order, o.filter);
      c = std::move(r);
    }
    s.order = o.order;
    s.isotropic = s_.isotropic || o.isotropic;
    s.filter = o.filter.name();
    s.source = text_;
    (void)ctx;
    return s;
  }

 private:
  Spectrum s_;
  std::optional<HalfAngleFactors> lobe_;
  std::string text_;
};

bool is_regular_file(const std::string& path) {
  struct stat st{};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

}  // namespace

int BrdfSource::largest_sample_order(bool) const { return -1; }
std::optional<HalfAngleNodes> BrdfSource::own_half_angle_nodes() const { return std::nullopt; }
std::optional<OwnHeldOut> BrdfSource::own_held_out(const HeldOutRequest&) const { return std::nullopt; }
std::optional<Eigen::MatrixXd> BrdfSource::noise_sigma_at(const RowMatrix3d&, const RowMatrix3d&) const { return std::nullopt; }

std::vector<std::string> channel_column_names(int channels) {
  if (channels == 1) return {"f"};
  if (channels == 3) return {"f_r", "f_g", "f_b"};
  std::vector<std::string> names;
  for (int c = 0; c < channels; ++c) names.push_back("f_" + std::to_string(c));
  return names;
}

std::vector<std::string> channel_column_names(const BrdfSource& source) {
  std::vector<std::string> names = source.channel_names();
  if (static_cast<int>(names.size()) != source.channels()) return channel_column_names(source.channels());
  for (auto& n : names) n = "f_" + n;
  return names;
}

std::unique_ptr<BrdfSource> spectrum_source(Spectrum spectrum) {
  const std::string text = spectrum.source;
  return std::make_unique<SpectrumSource>(std::move(spectrum), std::nullopt, text);
}

std::unique_ptr<BrdfSource> model_source(std::unique_ptr<BrdfModel> model) { return std::make_unique<ModelSource>(std::move(model)); }

std::unique_ptr<BrdfSource> open_source(const std::string& text) {
  if (is_model_source(text)) return std::make_unique<ModelSource>(parse_model_source(text));
  if (auto measured = open_measured_source(text)) return measured;  // MERL, RGL, CSV samples, SCATMECH (icobrdf/io/measured_sources.hpp)
  const auto [path, name] = split_material_ref(text);
  if (path.size() > 3 && path.compare(path.size() - 3, 3, ".h5") == 0) {
    if (!is_regular_file(path)) throw InputError(path + ": no such file (SOURCE '" + quoted_text(text) + "')");
    ReadOptions ro;
    ro.read_luts = false;
    MaterialRecord rec = read_bank_material(path, name, ro);
    return std::make_unique<SpectrumSource>(std::move(rec.spectrum), std::move(rec.lobe), text);
  }
  throw ArgumentError("unknown SOURCE '" + quoted_text(text) + "': expected model:NAME[:key=value,...] or FILE.h5[#MATERIAL]");
}

}  // namespace icobrdf
