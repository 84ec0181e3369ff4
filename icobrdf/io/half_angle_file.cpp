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

void write_factor(h5::Group& g, const char* dataset, const std::vector<RowMatrixXd>& m, Eigen::Index rows, int rank,
                  const char* unit, const std::string& description) {
  const size_t per = static_cast<size_t>(rows) * static_cast<size_t>(rank);
  std::vector<double> buf(per * m.size());
  for (size_t c = 0; c < m.size(); ++c)
    Eigen::Map<RowMatrixXd>(buf.data() + c * per, rows, rank) = m[c];
  g.write(dataset, buf.data(), Shape{u64(static_cast<std::int64_t>(m.size())), u64(rows), u64(rank)}, unit, description);
}

std::vector<RowMatrixXd> read_factor(const h5::Group& g, const char* dataset, int channels, std::int64_t rows, int rank,
                                     const h5::ReadLimits& lim) {
  auto a = g.read<double>(dataset, ShapePattern{channels, rows, rank}, lim);
  for (size_t i = 0; i < a.data.size(); ++i)
    if (!std::isfinite(a.data[i]))
      g.fail(g.child_path(dataset), "expected finite values, found " + std::to_string(a.data[i]) + " at flat index " +
                                        std::to_string(i));
  std::vector<RowMatrixXd> out(static_cast<size_t>(channels));
  const size_t per = static_cast<size_t>(rows) * static_cast<size_t>(rank);
  for (int c = 0; c < channels; ++c)
    out[static_cast<size_t>(c)] = Eigen::Map<const RowMatrixXd>(a.data.data() + static_cast<size_t>(c) * per, rows, rank);
  return out;
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
  write_factor(g, "u", lobe.u, lobe.h_nodes(), lobe.rank, "1/sr", "u[c, h node, r]: h factor of term r of " + q);
  write_factor(g, "v", lobe.v, lobe.d_nodes(), lobe.rank, "1", "v[c, d node, r]: d factor of term r of " + q);
}

nlohmann::json half_angle_summary(const HalfAngleFactors& l) {
  nlohmann::json terms = nlohmann::json::array();
  for (int c = 0; c < l.channels(); ++c) {
    std::vector<double> w;
    for (int r = 0; r < l.rank; ++r) w.push_back(l.u[c].col(r).norm() * l.v[c].col(r).norm());
    terms.push_back(w);
  }
  return {{"quantity", half_angle_quantity_name(l.quantity)}, {"isotropic", l.isotropic}, {"rank", l.rank}, {"n_t", l.n_t},
          {"n_phi_h", l.n_phi_h}, {"n_theta_d", l.n_theta_d}, {"n_phi_d", l.n_phi_d}, {"h_warp", l.h_warp},
          {"corners", horizon_corners_name(l.corners)}, {"nodes", l.centred ? "centres" : "ends"}, {"h_axis", l.h_axis}, {"h_scale_1", l.h_scale_1}, {"h_scale_2", l.h_scale_2},
          {"bytes", l.bytes()}, {"term_norms", terms}};
}

std::string half_angle_summary_line(const HalfAngleFactors& l, bool norms) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "half-angle lobe of %s (%s), rank %d, h nodes %d x %d (theta_h = (pi/2) t^%g), d nodes %d x %d, %zu bytes",
                quantity_text(l.quantity, false).c_str(), l.isotropic ? "isotropic" : "anisotropic",
                l.rank, l.n_t, l.n_phi_h, l.h_warp, l.n_theta_d, l.n_phi_d, l.bytes());
  std::string out = buf;
  if (l.centred) out += ", nodes at bin centres";
  if (l.stretched()) {
    std::snprintf(buf, sizeof buf, ", h grid stretched %.3g x %.3g along %.1f deg", l.h_scale_1, l.h_scale_2, l.h_axis * 180 / M_PI);
    out += buf;
  }
  for (int c = 0; norms && c < l.channels(); ++c) {
    out += "\n    channel " + std::to_string(c) + " term norms |u_r| |v_r|:";
    for (int r = 0; r < l.rank; ++r) {
      std::snprintf(buf, sizeof buf, " %.4g", l.u[c].col(r).norm() * l.v[c].col(r).norm());
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
  f.u = read_factor(g, "u", channels, std::int64_t{f.n_t} * f.n_phi_h, f.rank, lim);
  f.v = read_factor(g, "v", channels, std::int64_t{f.n_theta_d} * f.n_phi_d, f.rank, lim);
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
