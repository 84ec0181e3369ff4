#include "icobrdf/plot/plot_options.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/spectrum/spectrum_ops.hpp"
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

SliceSource load_slice_source(const std::string& text, std::vector<int>& orders, bool orders_given, int level) {
  if (orders.empty()) throw ArgumentError("--order: at least one truncation order is required");
  const int top_order = *std::max_element(orders.begin(), orders.end());
  SliceSource src = slice_source(load_picture_material(text, top_order, level, !orders_given && !is_model_source(text)));
  if (!src.spectrum) orders.clear();
  else if (top_order > src.spectrum->order)
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
  auto s = std::make_shared<const Spectrum>(std::move(*m.spectrum));
  v.channels = s->channel_count();
  if (s->cosine) v.quantity = "g = f cos(theta_i)";
  v.values = [s](const RowMatrix3d& wi, const RowMatrix3d& wr) {
    Eigen::MatrixXd out(wi.rows(), s->channel_count());
    for (int c = 0; c < s->channel_count(); ++c) out.col(c) = evaluate_coefficients(s->channels[c], s->order, wi, wr);
    return out;
  };
  return v;
}

}  // namespace icobrdf::plot
