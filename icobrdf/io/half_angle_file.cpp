#include "icobrdf/io/half_angle_file.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "icobrdf/core/support/error.hpp"

namespace icobrdf {
namespace {

using h5::Shape;
using h5::ShapePattern;

// Largest node count along one axis and largest rank accepted from a file: sanity bounds against overflow of
// the products below (the dataset size limit of the read applies first in practice).
constexpr std::int64_t kMaxAxisNodes = 1 << 16;
constexpr std::int64_t kMaxFactorRank = 4096;

const char* const kCoordinates =
    "h = normalize(w_i + w_r) with angles (theta_h, phi_h); d = w_i in the frame where h is the pole, "
    "d = Ry(-theta_h) Rz(-phi_h) w_i, angles (theta_d, phi_d) (Rusinkiewicz 1998; phi_h = 0 at h = +z). "
    "h nodes: t_k = k/(n_t-1) (nodes = centres: (k+1/2)/n_t, and likewise for theta_d and phi_d), theta_h = (pi/2) t^h_warp; phi_h_j = 2 pi j/n_phi_h (periodic; isotropic: "
    "n_phi_h = 1, no phi_h dependence). Anisotropic grids with a stretch (h_axis, h_scale_1, h_scale_2) take "
    "(theta_h, phi_h) of h' ~ (s_1/h_scale_1, s_2/h_scale_2, 1), s_1 = cos(a) s_x + sin(a) s_y, "
    "s_2 = -sin(a) s_x + cos(a) s_y, (s_x, s_y) = (h_x, h_y)/h_z, a = h_axis. d nodes: theta_d_a = (pi/2) a/(n_theta_d-1); phi_d_b = pi b/n_phi_d, "
    "periodic with period pi (reciprocity); anisotropic lobes measure phi_d from the world's x axis, "
    "phi_d + phi_h (the minimal rotation taking h to +z). Rows: u[k n_phi_h + j], v[a n_phi_d + b]. q = sum_r u v, linear "
    "in t and phi_h, bilinear in theta_d and phi_d; corners = valid: corner node pairs below the horizon "
    "(cos_h cos_d - sin_h sin_d |cos(phi_d - phi_h)| < 0, true angles) are dropped and the other weights renormalized; "
    "f = q (quantity f), q / (max(cos_i, cosine_floor) max(cos_r, cosine_floor)) (quantity cosine) or "
    "q / max((cos_i + cos_r)/2, cosine_floor) (quantity mean-cosine); f = 0 below the horizon.";

[[noreturn]] void bad_lobe(const std::string& name, const std::string& what) {
  throw ArgumentError("cannot write material '" + name + "': half-angle lobe: " + what);
}

std::string quantity_text(HalfAngleQuantity q, bool long_form) {
  if (q == HalfAngleQuantity::Cosine) return long_form ? "q = f cos(theta_i) cos(theta_r)" : "q = f cos_i cos_r";
  if (q == HalfAngleQuantity::MeanCosine) return long_form ? "q = f (cos(theta_i) + cos(theta_r))/2" : "q = f (cos_i + cos_r)/2";
  return "q = f";
}

std::uint64_t u64(std::int64_t n) { return static_cast<std::uint64_t>(n); }

// One factor (u or v) of every factor set in the lobe's precision: float64 / float32 values, or integers k
// with the per-column scales in <dataset>_scale (sets x rank, float64): value = scale * k.
void write_factor(h5::Group& g, const char* dataset, const std::vector<RowMatrixXd>& m, Eigen::Index rows, int rank, FactorPrecision p,
                  const char* unit, const std::string& description) {
  const size_t per = static_cast<size_t>(rows) * static_cast<size_t>(rank);
  const Shape shape{u64(static_cast<std::int64_t>(m.size())), u64(rows), u64(rank)};
  std::vector<double> buf(per * m.size());
  for (size_t c = 0; c < m.size(); ++c) Eigen::Map<RowMatrixXd>(buf.data() + c * per, rows, rank) = m[c];
  if (p == FactorPrecision::Float64) return g.write(dataset, buf.data(), shape, unit, description);
  if (p == FactorPrecision::Float32) {
    const std::vector<float> f(buf.begin(), buf.end());
    return g.write(dataset, f.data(), shape, unit, description);
  }
  std::vector<double> scales(m.size() * static_cast<size_t>(rank));
  // Only the stored width is filled: a value of the int16 range converted to int8 is undefined behaviour.
  const bool wide = p == FactorPrecision::Int16;
  std::vector<std::int16_t> k16(wide ? buf.size() : 0);
  std::vector<std::int8_t> k8(wide ? 0 : buf.size());
  for (size_t c = 0; c < m.size(); ++c)
    for (int r = 0; r < rank; ++r) {
      const double scale = HalfAngleFactors::column_scale(m[c].col(r), p);
      scales[c * static_cast<size_t>(rank) + static_cast<size_t>(r)] = scale;
      for (Eigen::Index i = 0; i < rows; ++i) {
        const double k = scale > 0.0 ? std::round(m[c](i, r) / scale) : 0.0;
        const size_t at = c * per + static_cast<size_t>(i) * static_cast<size_t>(rank) + static_cast<size_t>(r);
        if (wide)
          k16[at] = static_cast<std::int16_t>(k);
        else
          k8[at] = static_cast<std::int8_t>(k);
      }
    }
  const std::string what = description + " = " + dataset + "_scale[c, r] * this";
  if (wide)
    g.write(dataset, k16.data(), shape, "1", what);
  else
    g.write(dataset, k8.data(), shape, "1", what);
  g.write((std::string(dataset) + "_scale").c_str(), scales.data(), Shape{shape[0], u64(rank)}, unit,
          std::string("scale of each column of ") + dataset);
}

template <class T>
std::vector<double> read_values(const h5::Group& g, const char* dataset, const ShapePattern& shape, const h5::ReadLimits& lim) {
  auto a = g.read<T>(dataset, shape, lim);
  return std::vector<double>(a.data.begin(), a.data.end());
}

std::vector<RowMatrixXd> read_factor(const h5::Group& g, const char* dataset, int sets, std::int64_t rows, int rank, FactorPrecision p,
                                     const h5::ReadLimits& lim) {
  const ShapePattern shape{sets, rows, rank};
  std::vector<double> data = p == FactorPrecision::Float64   ? read_values<double>(g, dataset, shape, lim)
                             : p == FactorPrecision::Float32 ? read_values<float>(g, dataset, shape, lim)
                             : p == FactorPrecision::Int16   ? read_values<std::int16_t>(g, dataset, shape, lim)
                                                             : read_values<std::int8_t>(g, dataset, shape, lim);
  const size_t per = static_cast<size_t>(rows) * static_cast<size_t>(rank);
  if (const int levels = factor_precision_levels(p); levels > 0) {
    const std::string name = std::string(dataset) + "_scale";
    const auto scale = g.read<double>(name, ShapePattern{sets, rank}, lim);
    for (size_t i = 0; i < scale.data.size(); ++i)
      if (!(std::isfinite(scale.data[i]) && scale.data[i] >= 0.0))
        g.fail(g.child_path(name), "expected finite scales >= 0, found " + std::to_string(scale.data[i]) + " at flat index " + std::to_string(i));
    for (size_t i = 0; i < data.size(); ++i) {
      if (std::abs(data[i]) > levels)
        g.fail(g.child_path(dataset), "expected |k| <= " + std::to_string(levels) + ", found " + std::to_string(data[i]) + " at flat index " + std::to_string(i));
      const size_t set = i / per, r = i % static_cast<size_t>(rank);
      data[i] *= scale.data[set * static_cast<size_t>(rank) + r];
    }
  }
  for (size_t i = 0; i < data.size(); ++i)
    if (!std::isfinite(data[i]))
      g.fail(g.child_path(dataset), "expected finite values, found " + std::to_string(data[i]) + " at flat index " + std::to_string(i));
  std::vector<RowMatrixXd> out(static_cast<size_t>(sets));
  for (int c = 0; c < sets; ++c)
    out[static_cast<size_t>(c)] = Eigen::Map<const RowMatrixXd>(data.data() + static_cast<size_t>(c) * per, rows, rank);
  return out;
}

// |u_r| |v_r| of term r of channel c (times its channel scale when the factors are shared).
double term_norm(const HalfAngleFactors& l, int c, int r) {
  const size_t set = l.shared() ? 0 : static_cast<size_t>(c);
  return l.u[set].col(r).norm() * l.v[set].col(r).norm() * (l.shared() ? std::abs(l.channel_scales(c, r)) : 1.0);
}

}  // namespace

void write_half_angle(h5::Group& material, const HalfAngleFactors& lobe, int channels, const std::string& name) {
  if (lobe.rank < 1) bad_lobe(name, "expected rank >= 1, found " + std::to_string(lobe.rank));
  if (lobe.channels() != channels)
    bad_lobe(name, "expected " + std::to_string(channels) + " channel(s) as the spectrum, found " + std::to_string(lobe.channels()));
  try {
    lobe.validate();
  } catch (const InputError& e) {
    bad_lobe(name, e.what());
  }
  HalfAngleFactors stored = lobe;  // the values the file holds (those of a quantized lobe already)
  stored.quantize();
  h5::Group g = material.create_group(kHalfAngleGroup);
  g.set_attr("quantity", half_angle_quantity_name(lobe.quantity));
  g.set_attr("isotropic", lobe.isotropic);
  g.set_attr("h_warp", lobe.h_warp);
  g.set_attr("corners", horizon_corners_name(lobe.corners));
  g.set_attr("nodes", lobe.centred ? "centres" : "ends");
  g.set_attr("h_axis", lobe.h_axis);
  g.set_attr("h_scale_1", lobe.h_scale_1);
  g.set_attr("h_scale_2", lobe.h_scale_2);
  g.set_attr("n_t", static_cast<std::int32_t>(lobe.n_t));
  g.set_attr("n_phi_h", static_cast<std::int32_t>(lobe.n_phi_h));
  g.set_attr("n_theta_d", static_cast<std::int32_t>(lobe.n_theta_d));
  g.set_attr("n_phi_d", static_cast<std::int32_t>(lobe.n_phi_d));
  g.set_attr("rank", static_cast<std::int32_t>(lobe.rank));
  g.set_attr("cosine_floor", lobe.cosine_floor());
  g.set_attr("coordinates", kCoordinates);
  const std::string q = quantity_text(lobe.quantity, true);
  // Format 4.0: the precision and shared factor sets (absent: float64, one set per channel).
  if (lobe.precision != FactorPrecision::Float64) g.set_attr("precision", factor_precision_name(lobe.precision));
  if (lobe.shared()) {
    g.set_attr("factor_sets", "shared");
    g.write_matrix("channel_scales", lobe.channel_scales, "1",
                   "channel_scales[c, r]: weight of the shared term r in channel c, q_c = sum_r channel_scales[c, r] u[0, h, r] v[0, d, r]");
  }
  const std::string set = lobe.shared() ? "0" : "c";
  write_factor(g, "u", stored.u, lobe.h_nodes(), lobe.rank, lobe.precision, "1/sr", "u[" + set + ", h node, r]: h factor of term r of " + q);
  write_factor(g, "v", stored.v, lobe.d_nodes(), lobe.rank, lobe.precision, "1", "v[" + set + ", d node, r]: d factor of term r of " + q);
}

nlohmann::json half_angle_summary(const HalfAngleFactors& l) {
  nlohmann::json terms = nlohmann::json::array();
  for (int c = 0; c < l.channels(); ++c) {
    std::vector<double> w;
    for (int r = 0; r < l.rank; ++r) w.push_back(term_norm(l, c, r));
    terms.push_back(w);
  }
  return {{"quantity", half_angle_quantity_name(l.quantity)}, {"isotropic", l.isotropic}, {"rank", l.rank}, {"n_t", l.n_t},
          {"n_phi_h", l.n_phi_h}, {"n_theta_d", l.n_theta_d}, {"n_phi_d", l.n_phi_d}, {"h_warp", l.h_warp},
          {"corners", horizon_corners_name(l.corners)}, {"nodes", l.centred ? "centres" : "ends"}, {"h_axis", l.h_axis}, {"h_scale_1", l.h_scale_1}, {"h_scale_2", l.h_scale_2},
          {"bytes", l.bytes()}, {"precision", factor_precision_name(l.precision)}, {"factor_sets", l.shared() ? "shared" : "channels"},
          {"term_norms", terms}};
}

std::string half_angle_summary_line(const HalfAngleFactors& l, bool norms) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "half-angle lobe of %s (%s), rank %d, h nodes %d x %d (theta_h = (pi/2) t^%g), d nodes %d x %d, %zu bytes",
                quantity_text(l.quantity, false).c_str(), l.isotropic ? "isotropic" : "anisotropic",
                l.rank, l.n_t, l.n_phi_h, l.h_warp, l.n_theta_d, l.n_phi_d, l.bytes());
  std::string out = buf;
  if (l.centred) out += ", nodes at bin centres";
  if (l.precision != FactorPrecision::Float64) out += std::string(", ") + factor_precision_name(l.precision) + " factors";
  if (l.shared()) out += ", channels share the factors";
  if (l.stretched()) {
    std::snprintf(buf, sizeof buf, ", h grid stretched %.3g x %.3g along %.1f deg", l.h_scale_1, l.h_scale_2, l.h_axis * 180 / M_PI);
    out += buf;
  }
  for (int c = 0; norms && c < l.channels(); ++c) {
    out += "\n    channel " + std::to_string(c) + " term norms |u_r| |v_r|:";
    for (int r = 0; r < l.rank; ++r) {
      std::snprintf(buf, sizeof buf, " %.4g", term_norm(l, c, r));
      out += buf;
    }
  }
  return out;
}

HalfAngleFactors read_half_angle(const h5::Group& material, int channels, const h5::ReadLimits& lim) {
  const h5::Group g = material.open_group(kHalfAngleGroup);
  g.check_links();
  HalfAngleFactors f;
  const std::string quantity = g.attr_string("quantity");
  try {
    f.quantity = half_angle_quantity_from_name(quantity);
  } catch (const ArgumentError&) {
    g.fail(g.path(), "attribute quantity: expected 'f', 'cosine' or 'mean-cosine', found '" + quantity + "'");
  }
  f.isotropic = g.attr_bool("isotropic");
  f.h_warp = g.attr_double("h_warp");
  // Format 2.x lobes have none of these: every corner interpolates, no stretch.
  f.corners = HorizonCorners::All;
  if (g.has_attr("corners")) {
    const std::string corners = g.attr_string("corners");
    try {
      f.corners = horizon_corners_from_name(corners);
    } catch (const ArgumentError&) {
      g.fail(g.path(), "attribute corners: expected 'all' or 'valid', found '" + corners + "'");
    }
  }
  if (g.has_attr("nodes")) {
    const std::string nodes = g.attr_string("nodes");
    if (nodes != "ends" && nodes != "centres") g.fail(g.path(), "attribute nodes: expected 'ends' or 'centres', found '" + nodes + "'");
    f.centred = nodes == "centres";
  }
  if (g.has_attr("h_axis")) f.h_axis = g.attr_double("h_axis");
  if (g.has_attr("h_scale_1")) f.h_scale_1 = g.attr_double("h_scale_1");
  if (g.has_attr("h_scale_2")) f.h_scale_2 = g.attr_double("h_scale_2");
  f.n_t = static_cast<int>(g.attr_int("n_t", 2, kMaxAxisNodes));
  f.n_phi_h = static_cast<int>(g.attr_int("n_phi_h", 1, kMaxAxisNodes));
  f.n_theta_d = static_cast<int>(g.attr_int("n_theta_d", 2, kMaxAxisNodes));
  f.n_phi_d = static_cast<int>(g.attr_int("n_phi_d", 1, kMaxAxisNodes));
  f.rank = static_cast<int>(g.attr_int("rank", 1, kMaxFactorRank));
  const double floor = g.attr_double("cosine_floor");
  // Format 4.0 storage (absent: float64, a factor set per channel).
  if (g.has_attr("precision")) {
    const std::string p = g.attr_string("precision");
    try {
      f.precision = factor_precision_from_name(p);
    } catch (const ArgumentError&) {
      g.fail(g.path(), "attribute precision: expected 'float64', 'float32', 'int16' or 'int8', found '" + p + "'");
    }
  }
  int sets = channels;
  if (g.has_attr("factor_sets")) {
    const std::string s = g.attr_string("factor_sets");
    if (s != "shared" && s != "channels") g.fail(g.path(), "attribute factor_sets: expected 'shared' or 'channels', found '" + s + "'");
    if (s == "shared") {
      sets = 1;
      const auto m = g.read<double>("channel_scales", ShapePattern{channels, f.rank}, lim);
      f.channel_scales = Eigen::Map<const RowMatrixXd>(m.data.data(), channels, f.rank);
    }
  }
  f.u = read_factor(g, "u", sets, std::int64_t{f.n_t} * f.n_phi_h, f.rank, f.precision, lim);
  f.v = read_factor(g, "v", sets, std::int64_t{f.n_theta_d} * f.n_phi_d, f.rank, f.precision, lim);
  try {
    f.validate();
  } catch (const InputError& e) {
    g.fail(g.path(), e.what());
  }
  // The floor follows from the grid (sin((pi/2) / (n_theta_d - 1))); a file that disagrees was not written
  // by this definition.
  if (std::abs(floor - f.cosine_floor()) > 1e-15)
    g.fail(g.path(), "attribute cosine_floor: expected " + std::to_string(f.cosine_floor()) + " for n_theta_d = " +
                         std::to_string(f.n_theta_d) + ", found " + std::to_string(floor));
  return f;
}

}  // namespace icobrdf
