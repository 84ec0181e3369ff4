#include "icobrdf/io/bank_summary.hpp"

#include <fmt/core.h>

#include "icobrdf/io/half_angle_file.hpp"

namespace icobrdf {

nlohmann::json bank_summary_json(const BankContents& b, const std::string& path) {
  nlohmann::json mats = nlohmann::json::array();
  for (const auto& m : b.materials) {
    nlohmann::json j{{"name", m.name}, {"source", m.spectrum.source}, {"order", m.spectrum.order}, {"isotropic", m.spectrum.isotropic},
                     {"cosine", m.spectrum.cosine}, {"channels", m.spectrum.channel_count()}, {"level", m.spectrum.level},
                     {"grid", m.spectrum.grid_kind}, {"has_lut", !m.lut.empty() || m.lut_float32},
                     {"representation", representation_name(m)}};
    if (m.lobe) j["half_angle"] = half_angle_summary(*m.lobe);
    for (const auto& [k, v] : m.figures) j[k] = v;
    for (const auto& [k, v] : m.labels) j[k] = v;
    mats.push_back(j);
  }
  nlohmann::json j{{"file", path}, {"format_version", b.format_version}, {"creator", b.creator}, {"created", b.created},
                   {"grid", b.grid ? nlohmann::json{{"kind", to_string(b.grid->kind)}, {"level", b.grid->level}, {"cells", b.grid->cells()}} : nlohmann::json()},
                   {"materials", mats}};
  nlohmann::json basis = nlohmann::json::array();
  for (const auto& a : b.basis) basis.push_back(a.path);
  j["basis"] = basis;
  return j;
}

std::string bank_summary_text(const BankContents& b, const std::string& path) {
  std::string out = fmt::format("{}: icobrdf bank {} by {}, created {}\n", path, b.format_version, b.creator, b.created);
  if (b.grid) out += fmt::format("  grid: {} level {} ({} cells)\n", to_string(b.grid->kind), b.grid->level, b.grid->cells());
  out += fmt::format("  basis arrays: {}\n", b.basis.size());
  for (const auto& m : b.materials) {
    out += fmt::format("  {:<18} order {:>2} {:<11} {} channel(s)  {}\n", m.name, m.spectrum.order,
                       m.spectrum.isotropic ? "isotropic" : "anisotropic", m.spectrum.channel_count(), m.spectrum.source);
    if (m.lobe) out += fmt::format("  {:<18} {}: {}\n", "", representation_name(m), half_angle_summary_line(*m.lobe));
  }
  return out;
}

}  // namespace icobrdf
