#include "icobrdf/pipeline/bank_report.hpp"

#include <fmt/core.h>

#include <cmath>

#include "icobrdf/core/support/error.hpp"

namespace icobrdf {

nlohmann::json material_report_json(const MaterialReport& m) {
  nlohmann::json j{{"name", m.name}, {"source", m.source}, {"ok", m.ok}, {"resumed", m.resumed}};
  if (m.rank >= 0) j["rank"] = m.rank;  // under mpirun: the rank that fitted it
  if (!m.ok) {
    j["error"] = m.error;
    return j;
  }
  j.update({{"representation", m.representation}, {"isotropic", m.isotropic}, {"level", m.level}, {"order", m.order}, {"target", m.target},
            {"error_measured", m.measured}, {"error_l2", m.measured ? nlohmann::json(m.error_l2) : nlohmann::json()},
            {"error_max", m.measured ? nlohmann::json(m.error_max) : nlohmann::json()}, {"metric", m.metric},
            {"asymmetry", m.measured && std::isfinite(m.asymmetry) ? nlohmann::json(m.asymmetry) : nlohmann::json()},
            {"noise", m.measured && std::isfinite(m.noise) ? nlohmann::json(m.noise) : nlohmann::json()},
            {"judged_against", m.reciprocal_reference ? "reciprocal part" : "data"},
            {"grazing_share", m.measured ? nlohmann::json(m.grazing_share) : nlohmann::json()}, {"anisotropy", m.anisotropy},
            {"kept_coefficients", m.kept}, {"total_coefficients", m.total}, {"bytes", m.bytes}, {"seconds", m.seconds},
            {"target_met", m.target_met}, {"max_bytes", m.max_bytes >= 0 ? nlohmann::json(m.max_bytes) : nlohmann::json()},
            {"below_noise", m.below_noise}, {"lobe_floor", std::isfinite(m.lobe_floor) ? nlohmann::json(m.lobe_floor) : nlohmann::json()},
            {"note", m.note}});
  return j;
}

std::string bank_build_table(const BankBuildResult& r, const std::string& output) {
  std::string out = fmt::format("{:<18} {:<10} {:>4} {:>5} {:>5} {:>9} {:>4} {:>9} {:>9} {:>9} {:>9} {:>11} {:>8} {:>7}\n", "material", "repr",
                                "iso", "level", "order", "target", "met", "rel L2", "rel max", "asym", "noise", "kept/total", "bytes", "seconds");
  const auto dash = [](int v) { return v < 0 ? std::string("-") : std::to_string(v); };  // no modes: a lobe alone
  for (const auto& m : r.materials) {
    if (!m.ok) {
      out += fmt::format("{:<18} FAILED{}: {}\n", m.name, m.rank >= 0 ? fmt::format(" on rank {}", m.rank) : "", m.error);
      continue;
    }
    const std::string l2 = m.measured ? fmt::format("{:.3g}", m.error_l2) : "n/a", mx = m.measured ? fmt::format("{:.3g}", m.error_max) : "n/a";
    const std::string asym = m.measured && std::isfinite(m.asymmetry) ? fmt::format("{:.3g}", m.asymmetry) : "n/a";
    const std::string noise = m.measured && std::isfinite(m.noise) ? fmt::format("{:.3g}", m.noise) : "n/a";
    const char* met = !m.measured ? "n/a" : m.target_met ? "yes" : std::isfinite(m.lobe_floor) ? "floor" : m.below_noise ? "noise" : "NO";
    out += fmt::format("{:<18} {:<10} {:>4} {:>5} {:>5} {:>9.3g} {:>4} {:>9} {:>9} {:>9} {:>9} {:>11} {:>8} {:>7.2f}{}\n", m.name, m.representation,
                       m.isotropic ? "yes" : "no", dash(m.level), dash(m.order), m.target, met, l2, mx, asym, noise,
                       fmt::format("{}/{}", m.kept, m.total), m.bytes, m.seconds, m.resumed ? " (resumed)" : "");
  }
  for (const auto& m : r.materials)
    if (m.ok && m.measured && m.reciprocal_reference && m.target < m.asymmetry)
      out += fmt::format("note: {}: target {:.3g} is below the data's own asymmetry {:.3g}: the error is against their reciprocal part "
                         "(f + f^T)/2; against the raw data no reciprocal BRDF comes closer than {:.3g}\n",
                         m.name, m.target, m.asymmetry, m.asymmetry);
  for (const auto& m : r.materials)
    if (m.ok && !m.note.empty()) out += fmt::format("note: {}: target {:.3g} missed ({:.3g}): {}\n", m.name, m.target, m.error_l2, m.note);
  for (const auto& m : r.materials)
    if (m.ok && m.measured && m.metric == "f" && m.grazing_share > kGrazingDominates)
      out += fmt::format("note: {}: {:.0f}% of the reference's norm is from pairs beyond 80 deg, which metric \"f\" weighs fully "
                         "and a renderer scales by cos theta < 0.17 (metric \"cosine\" is the default)\n",
                         m.name, 100 * m.grazing_share);
  if (r.written) out += fmt::format("wrote {}\n", output);
  return out;
}

std::size_t targets_missed(const BankBuildResult& r) {
  std::size_t missed = 0;
  for (const auto& m : r.materials) missed += m.ok && !m.target_met;
  return missed;
}

std::string targets_missed_message(std::size_t missed) {
  return fmt::format("{} material(s) missed their target and were written with the lowest error within their max_bytes "
                     "(on_miss = \"keep-best\")", missed);
}

nlohmann::json bank_build_json(const BankBuildResult& r, const std::string& scene, const std::string& output) {
  nlohmann::json mats = nlohmann::json::array();
  for (const auto& m : r.materials) mats.push_back(material_report_json(m));
  return {{"scene", scene}, {"output", output}, {"written", r.written}, {"interrupted", r.interrupted},
          {"resume_file", r.resume_file}, {"materials", mats}};
}

std::string bank_not_written_message(const BankBuildResult& r) {
  size_t failed = 0;
  const MaterialReport* first = nullptr;
  for (const auto& m : r.materials) {
    failed += !m.ok;
    if (!m.ok && !first) first = &m;
  }
  // Under mpirun the line names the first failed material and its rank (a long build's table is far above).
  const std::string which =
      first && first->rank >= 0 ? fmt::format("material '{}' failed on rank {}: {}; ", first->name, first->rank, message_line(first->error)) : "";
  return fmt::format("bank not written: {}{} material(s) failed (see above); {}", which, failed, kept_for_resume(r));
}

}  // namespace icobrdf
