#include "icobrdf/pipeline/source_albedo.hpp"

#include <fmt/core.h>

#include <cmath>
#include <memory>

#include "icobrdf/core/models/kernel_albedo_polynomial.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/pipeline/lut_material.hpp"
#include "icobrdf/pipeline/reflectance_check.hpp"
#include "icobrdf/pipeline/source_model.hpp"

namespace icobrdf {
namespace {

constexpr double kDegree = M_PI / 180.0;

std::string rule_text(const AlbedoRule& r) {
  return fmt::format("Gauss-Legendre in cos(theta_v), 2 x {} nodes split at the sun's cos(theta_s), x Gauss-Legendre in the relative azimuth, "
                     "2 x {} nodes split at the sun's plane; white-sky: {} Gauss-Legendre nodes in cos(theta_s); anisotropic sources: mean over {} sun azimuths",
                     r.polar_nodes, r.azimuth_nodes, r.sun_polar_nodes, r.sun_azimuths);
}

std::vector<double> row_values(const Eigen::Ref<const Eigen::RowVectorXd>& r) { return {r.data(), r.data() + r.size()}; }

// NaN anywhere: the source has no value at some quadrature pairs. Refused with what to do instead.
void require_values(const Eigen::Ref<const Eigen::MatrixXd>& a, const std::string& label, const std::string& what) {
  if (!a.hasNaN()) return;
  throw InputError("albedo of '" + quoted_text(label) + "': the source has no value (NaN) at some of the quadrature's pairs for the " + what +
                   " (e.g. a MERL table's empty bins): fit it first (icobrdf fit ... -o S.h5) and take the albedo of S.h5");
}

// Black-sky entries at the zeniths `deg`, checked, with the ATBD polynomial beside when the model has one.
nlohmann::json black_sky_entries(const BrdfModel& model, const std::string& label, const std::vector<double>& deg, const AlbedoRequest& q,
                                 std::ostream* warnings, const std::string& what) {
  Eigen::VectorXd theta(static_cast<Eigen::Index>(deg.size()));
  for (size_t k = 0; k < deg.size(); ++k) {
    if (!(deg[k] >= 0.0 && deg[k] <= 90.0))
      throw ArgumentError(fmt::format("albedo of '{}': a solar zenith must be in [0, 90] degrees, found {}", quoted_text(label), deg[k]));
    theta(static_cast<Eigen::Index>(k)) = deg[k] * kDegree;
  }
  const Eigen::MatrixXd a = black_sky_albedo(model, theta, q.rule);
  require_values(a, label, what);
  check_reflectance(a, "albedo of '" + quoted_text(label) + "'", "the quadrature of the " + what, "black-sky albedo", {q.strict, warnings});
  nlohmann::json out = nlohmann::json::array();
  for (size_t k = 0; k < deg.size(); ++k) {
    nlohmann::json e = {{"sza_deg", deg[k]}, {"albedo", row_values(a.row(static_cast<Eigen::Index>(k)))}};
    if (const auto p = atbd_black_sky_of(model, theta(static_cast<Eigen::Index>(k)))) e["atbd_polynomial"] = *p;
    out.push_back(e);
  }
  return out;
}

std::vector<std::string> column_names(const nlohmann::json& j) {
  std::vector<std::string> names = j["channel_names"].get<std::vector<std::string>>();
  const int channels = j["channels"].get<int>();
  if (static_cast<int>(names.size()) == channels) return names;
  if (channels == 1) return {"albedo"};
  names.clear();
  for (int c = 0; c < channels; ++c) names.push_back(channels == 3 ? std::string(1, "rgb"[c]) : "channel_" + std::to_string(c));
  return names;
}

std::string lut_text(const nlohmann::json& j) {
  const nlohmann::json& ch = j["channels"];
  std::string out = fmt::format("{} '{}' ({} cells):\n", j["file"].get<std::string>(), j["material"].get<std::string>(), j["cells"].get<int>());
  for (size_t c = 0; c < ch.size(); ++c)
    out += fmt::format("  channel {}: directional albedo max {:.6g} (at theta {:.1f} deg, phi {:.1f} deg), min {:.6g}, mean {:.6g}: {}\n", c,
                       ch[c]["max_albedo"].get<double>(), ch[c]["worst_theta_deg"].get<double>(), ch[c]["worst_phi_deg"].get<double>(),
                       ch[c]["min_albedo"].get<double>(), ch[c]["mean_albedo"].get<double>(),
                       ch[c]["min_albedo"].get<double>() < 0                ? "NON-PHYSICAL (negative albedo)"
                       : ch[c]["energy_conserving"].get<bool>() ? "passes the white furnace"
                                                                 : "FAILS the white furnace (albedo > 1)");
  return out;
}

// One table of entries {sza_deg, albedo, [atbd_polynomial]}.
std::string zenith_table(const std::string& title, const nlohmann::json& entries, const std::vector<std::string>& names) {
  bool atbd = !entries.empty() && entries[0].contains("atbd_polynomial");
  std::string out = "  " + title + ":\n    " + fmt::format("{:>8}", "sza_deg");
  for (const auto& n : names) out += fmt::format(" {:>12}", n);
  out += atbd ? fmt::format(" {:>16}\n", "atbd_polynomial") : "\n";
  for (const auto& e : entries) {
    out += fmt::format("    {:>8g}", e["sza_deg"].get<double>());
    for (const auto& v : e["albedo"]) out += fmt::format(" {:>12.7f}", v.get<double>());
    out += atbd ? fmt::format(" {:>16.7f}\n", e["atbd_polynomial"].get<double>()) : "\n";
  }
  return out;
}

}  // namespace

bool asks_lut_albedo(const AlbedoRequest& q) {
  if (!q.black_sky_deg.empty() || q.white_sky || q.curve) return false;
  const std::string path = split_material_ref(q.input).path;
  return path.size() > 3 && path.compare(path.size() - 3, 3, ".h5") == 0;
}

nlohmann::json model_albedo_json(const BrdfModel& model, const std::string& label, const std::vector<std::string>& channel_names,
                                 const AlbedoRequest& q, std::ostream* warnings) {
  check_albedo_rule(q.rule);
  const AlbedoRule& r = q.rule;
  nlohmann::json j = {{"source", label},
                      {"channels", model.channels()},
                      {"channel_names", channel_names},
                      {"quadrature",
                       {{"rule", rule_text(r)},
                        {"polar_nodes", r.polar_nodes},
                        {"azimuth_nodes", r.azimuth_nodes},
                        {"sun_polar_nodes", r.sun_polar_nodes},
                        {"sun_azimuths", model.is_isotropic() ? 1 : r.sun_azimuths}}}};
  const bool defaults = q.black_sky_deg.empty() && !q.white_sky && !q.curve;
  if (q.white_sky || defaults) {
    const Eigen::RowVectorXd a = white_sky_albedo(model, r);
    require_values(a, label, "white-sky albedo");
    check_reflectance(a, "albedo of '" + quoted_text(label) + "'", "the quadrature of the white-sky albedo", "white-sky albedo", {q.strict, warnings});
    j["white_sky"] = row_values(a);
    if (const auto p = atbd_white_sky_of(model)) j["atbd_white_sky"] = *p;
  }
  if (!q.black_sky_deg.empty()) j["black_sky"] = black_sky_entries(model, label, q.black_sky_deg, q, warnings, "black-sky albedo");
  if (q.curve || defaults) {
    std::vector<double> deg;
    for (int d = 0; d <= kAlbedoCurveLastDeg; ++d) deg.push_back(d);
    j["curve"] = black_sky_entries(model, label, deg, q, warnings, "directional albedo curve");
  }
  return j;
}

nlohmann::json albedo_json(const AlbedoRequest& q, std::ostream* warnings) {
  if (asks_lut_albedo(q)) return lut_albedo_json(q.input, q.strict, warnings);
  std::string label;
  std::vector<std::string> names;
  const auto model = model_of_source(q.input, &label, &names);
  return model_albedo_json(*model, label, names, q, warnings);
}

std::string albedo_text(const nlohmann::json& j) {
  if (j.contains("cells")) return lut_text(j);
  const std::vector<std::string> names = column_names(j);
  const int channels = j["channels"].get<int>();
  std::string out = fmt::format("{} ({} channel{})\n  quadrature: {}\n", j["source"].get<std::string>(), channels, channels == 1 ? "" : "s",
                                j["quadrature"]["rule"].get<std::string>());
  if (j.contains("white_sky")) {
    out += "  white-sky albedo:";
    for (size_t c = 0; c < names.size(); ++c) out += fmt::format(" {} {:.7f}", names[c], j["white_sky"][c].get<double>());
    out += j.contains("atbd_white_sky") ? fmt::format(" (ATBD: {:.7f})\n", j["atbd_white_sky"].get<double>()) : "\n";
  }
  if (j.contains("black_sky")) out += zenith_table("black-sky albedo", j["black_sky"], names);
  if (j.contains("curve")) out += zenith_table("directional albedo curve (black-sky)", j["curve"], names);
  return out;
}

}  // namespace icobrdf
