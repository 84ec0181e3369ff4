#include "icobrdf/plot/plot_options.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>

#include "icobrdf/core/basis/lowpass_filter.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/spectrum/spectrum_ops.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/measured_sources.hpp"
#include "icobrdf/io/spectrum_file.hpp"
#include "icobrdf/pipeline/fit_order.hpp"
#include "icobrdf/pipeline/fit_source.hpp"
#include "icobrdf/plot/picture_materials.hpp"

namespace icobrdf::plot {

std::pair<double, double> parse_light(const std::string& s) {
  std::istringstream in(s);
  double t = NAN, p = NAN;
  char comma = 0;
  if (!(in >> t >> comma >> p) || comma != ',' || !(in >> std::ws).eof() || !(t >= 0 && t <= 180) || !std::isfinite(p))
    throw ArgumentError("--light '" + quoted_text(s) + "': expected THETA,PHI in degrees, 0 <= THETA <= 180, e.g. 45,135");
  return {t, p};
}

SphereRequest::Shading parse_shading(const std::string& s) {
  if (s == "auto") return SphereRequest::Shading::Auto;
  if (s == "model") return SphereRequest::Shading::Model;
  if (s == "spectrum") return SphereRequest::Shading::Spectrum;
  throw ArgumentError("--shading: expected auto, model or spectrum, found '" + quoted_text(s) + "'");
}

SphereRequest sphere_request(const std::string& light, double sky, double exposure, int size, const std::string& shading) {
  SphereRequest q;
  const auto [theta, phi] = parse_light(light);
  q.light_theta = theta * M_PI / 180;
  q.light_phi = phi * M_PI / 180;
  q.sky = sky;
  q.exposure = exposure;
  q.size = size;
  q.shading = parse_shading(shading);
  return q;
}

SliceRequest slice_request(double theta_i_deg, double phi_i_deg, const std::string& filter, int panel, bool exact, bool log) {
  SliceRequest q;
  q.theta_i = theta_i_deg * M_PI / 180;
  q.phi_i = phi_i_deg * M_PI / 180;
  q.filter = parse_lowpass_filter(filter);
  q.panel = panel;
  q.exact = exact;
  q.log = log;
  return q;
}

Spectrum load_spectrum_picture(const std::string& text) {
  const MaterialRef ref = split_material_ref(text);
  if (ref.path.size() < 4 || ref.path.compare(ref.path.size() - 3, 3, ".h5") != 0)
    throw ArgumentError("plot spectrum '" + quoted_text(text) + "': expected SPECTRUM.h5[#material]");
  return read_spectrum_file(ref.path, ref.name, "plot spectrum draws Zernike modes only; draw it with plot slice or plot sphere");
}

namespace {

// The values of a spectrum at direction pairs (pairs x channels): of f, or of g for a spectrum of g.
PairFunction spectrum_values(Spectrum spectrum) {
  auto s = std::make_shared<const Spectrum>(std::move(spectrum));
  return [s](const RowMatrix3d& wi, const RowMatrix3d& wr) {
    Eigen::MatrixXd out(wi.rows(), s->channel_count());
    for (int c = 0; c < s->channel_count(); ++c) out.col(c) = evaluate_coefficients(s->channels[c], s->order, wi, wr);
    return out;
  };
}

}  // namespace

SliceSource load_slice_source(const std::string& text, std::vector<int>& orders, bool orders_given, int level) {
  if (orders.empty()) throw ArgumentError("--order: at least one truncation order is required");
  const int top_order = *std::max_element(orders.begin(), orders.end());
  SliceSource src = slice_source(load_picture_material(text, top_order, level, !orders_given && !is_model_source(text)));
  if (!orders_given && src.exact && !is_model_source(text)) src.spectrum.reset();  // a stored lobe: its values alone
  if (!src.spectrum) {
    orders.clear();
  } else if (!orders_given) {  // a stored spectrum: the default orders up to its own, and its own
    const int own = src.spectrum->order;
    orders.erase(std::remove_if(orders.begin(), orders.end(), [own](int o) { return o > own; }), orders.end());
    if (orders.empty() || orders.back() != own) orders.push_back(own);
  } else if (top_order > src.spectrum->order)
    throw ArgumentError(fmt::format("--order {}: the spectrum of '{}' has order {}", top_order, quoted_text(text), src.spectrum->order));
  return src;
}

PictureValues load_picture_values(const std::string& text, int order, int level) {
  PictureMaterial m = load_picture_material(text, order, level, true);
  PictureValues v;
  if (m.exact) {
    v.values = std::move(m.exact);
    v.channels = m.exact_channels;
    return v;
  }
  v.channels = m.spectrum->channel_count();
  if (m.spectrum->cosine) v.quantity = "g = f cos(theta_i)";
  v.values = spectrum_values(std::move(*m.spectrum));
  return v;
}

SamplePicture load_sample_picture(const std::string& text, int order, int level) {
  const std::unique_ptr<BrdfSource> source = open_source(text);
  const BrdfSamples* own = samples_of(*source);
  if (!own)
    throw ArgumentError("SOURCE '" + quoted_text(text) + "': no samples of its own to draw, expected CSV samples or curet:FILE#sample=N");
  FitRequest r;
  r.level = level;
  r.order = fit_order_for(*source, order >= 0 ? std::optional<int>(order) : std::nullopt);
  Spectrum spectrum = fit_source(*source, r).spectrum;
  SamplePicture out;
  out.samples.wi = own->wi;
  out.samples.wr = own->wr;
  out.samples.values = own->values.rowwise().mean();
  const std::string how = spectrum.sample_fit && !spectrum.sample_fit->order_choice.empty() ? spectrum.sample_fit->order_choice : "given";
  out.fit_label = std::string(spectrum.isotropic ? "isotropic" : "general") + " modes of order " + std::to_string(spectrum.order) + " (" + how + ")";
  out.fit = spectrum_values(std::move(spectrum));
  return out;
}

}  // namespace icobrdf::plot
