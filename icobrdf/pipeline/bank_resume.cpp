#include "icobrdf/pipeline/bank_resume.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>

#include "icobrdf/pipeline/keys.hpp"

namespace icobrdf {
namespace {

// Time between two rewrites of OUTPUT.partial over the duration of the last rewrite (at most
// 1/(1 + ratio) = 9% of a build is spent on them; a SIGKILL loses at most ratio x that duration).
constexpr double kCheckpointRatio = 10.0;
// And at least this long between two rewrites after the first: in a build of cheap materials a rewrite of
// 100 materials at level 4 takes tens of milliseconds, and the ratio alone let the rewrites take their full
// 9% (0.34 s of a 3.8 s bank of 100, benchmarks/RESULTS.md); a SIGKILL then loses at most a second more.
constexpr double kMinCheckpointSeconds = 1.0;

}  // namespace

std::string material_key(const Scene& s, const SceneMaterial& m) {
  // v2: the name is part of the key, because the held-out pairs and the lobe's peak samples are seeded by it
  // (pipeline/held_out.cpp): two materials of one source but different names have different figures and may
  // choose differently. A v1 resume file matches nothing, so its materials are fitted again.
  std::string t = "icobrdf-bank-material-v2|" + m.name + "|" + m.source + "|" + exact_decimal(m.target) + "|" + to_string(m.isotropic) + "|" +
                  std::to_string(m.order) + "|" + std::to_string(m.level) + "|" + to_string(m.metric) + "|" + exact_decimal(m.incidence_min) +
                  "|" + exact_decimal(m.incidence_max) + "|" + (m.prune ? "prune" : "keep");
  for (const auto& d : m.lights) t += "|L" + exact_decimal(d.first) + "," + exact_decimal(d.second);
  for (const auto& d : m.cameras) t += "|C" + exact_decimal(d.first) + "," + exact_decimal(d.second);
  t += "|bank|" + std::to_string(s.level) + "|" + std::to_string(s.order_max) + "|" + to_string(s.sampling) + "|" +
       std::to_string(s.holdout_pairs) + "|" + (s.store_lut ? "lut" : "nolut") + (s.lut_float32 ? "32" : "64");
  for (int l : s.levels) t += "|" + std::to_string(l);
  t += "|repr";
  for (const auto& r : s.representations) t += "|" + r;
  if (!m.reciprocal) t += "|raw";
  // Budgets: nothing for the defaults (no budget, "fail"), so that earlier keys hold.
  if (m.max_bytes >= 0) t += "|max" + std::to_string(m.max_bytes);
  if (m.on_miss != OnMiss::Fail) t += "|" + to_string(m.on_miss);  // judged against the raw data (the default adds nothing: earlier keys hold)
  return fnv1a_hex(t);
}

std::optional<std::map<std::string, MaterialRecord>> read_resume_file(const std::string& partial_path) {
  if (::access(partial_path.c_str(), F_OK) != 0) return std::nullopt;
  std::map<std::string, MaterialRecord> previous;
  for (auto& rec : read_bank(partial_path).materials) {
    const auto it = rec.labels.find("key");
    if (it != rec.labels.end()) previous.emplace(it->second, std::move(rec));
  }
  return previous;
}

void store_choice(MaterialRecord& rec, const MaterialReport& rep) {
  rec.figures = {{"target", rep.target},         {"error_l2", rep.error_l2},     {"error_max", rep.error_max},
                 {"kept_coefficients", rep.kept}, {"total_coefficients", rep.total}, {"bytes", static_cast<double>(rep.bytes)},
                 {"seconds", rep.seconds},        {"fit_level", rep.level},        {"grazing_share", rep.grazing_share},
                 {"asymmetry", rep.asymmetry},    {"max_bytes", static_cast<double>(rep.max_bytes)}};
  rec.labels = {{"key", rep.key}, {"error_measured", rep.measured ? "yes" : "no (delta BRDF)"}, {"metric", rep.metric},
                {"judged_against", rep.reciprocal_reference ? "reciprocal part" : "data"},
                {"target_met", rep.target_met ? "yes" : "no"}};
  // Named for a lobe only: a material of modes alone is stored as before (the material's group says the rest).
  if (rep.representation != "modes") rec.labels["representation"] = rep.representation;
  if (!rep.note.empty()) rec.labels["note"] = rep.note;
  if (!rep.target_met) rec.labels["below_noise"] = rep.below_noise ? "yes" : "no";
  if (std::isfinite(rep.lobe_floor)) rec.figures["lobe_floor"] = rep.lobe_floor;
  if (std::isfinite(rep.noise)) rec.figures["noise"] = rep.noise;  // optional: absent when the source has no grid
}

void report_from_record(const MaterialRecord& rec, MaterialReport& rep) {
  rep.resumed = true;
  rep.source = rec.spectrum.source;
  rep.isotropic = rec.spectrum.isotropic && (!rec.lobe || rec.lobe->isotropic);
  rep.representation = representation_name(rec);
  rep.order = rec.spectrum.order;
  auto fig = [&](const char* k) { return rec.figures.count(k) ? rec.figures.at(k) : std::nan(""); };
  rep.level = static_cast<int>(fig("fit_level"));
  rep.target = fig("target");
  rep.error_l2 = fig("error_l2");
  rep.error_max = fig("error_max");
  rep.kept = static_cast<int>(fig("kept_coefficients"));
  rep.total = static_cast<int>(fig("total_coefficients"));
  rep.bytes = static_cast<long long>(fig("bytes"));
  rep.seconds = fig("seconds");
  rep.grazing_share = fig("grazing_share");
  rep.asymmetry = fig("asymmetry");
  rep.noise = fig("noise");
  rep.max_bytes = rec.figures.count("max_bytes") ? static_cast<long long>(fig("max_bytes")) : -1;
  rep.target_met = !(rec.labels.count("target_met") && rec.labels.at("target_met") == "no");
  rep.reciprocal_reference = rec.labels.count("judged_against") && rec.labels.at("judged_against") == "reciprocal part";
  if (rec.labels.count("metric")) rep.metric = rec.labels.at("metric");
  if (rec.labels.count("note")) rep.note = rec.labels.at("note");
  rep.below_noise = rec.labels.count("below_noise") && rec.labels.at("below_noise") == "yes";
  rep.lobe_floor = fig("lobe_floor");
  rep.anisotropy = rec.spectrum.anisotropy_fraction;
  rep.measured = !(rec.labels.count("error_measured") && rec.labels.at("error_measured") != "yes");
}

bool checkpoint_due(bool written_before, double since_last_s, double last_write_s) {
  return !written_before || since_last_s >= std::max(kCheckpointRatio * last_write_s, kMinCheckpointSeconds);
}

// The whole file is rewritten each time (atomically), so its cost grows with the materials finished
// (checkpoint_due says when).
void Checkpointer::maybe_write(const BankContents& done, bool force) {
  if (done.materials.size() == saved_) return;
  const auto t = std::chrono::steady_clock::now();
  if (!force && !checkpoint_due(saved_ > 0, std::chrono::duration<double>(t - last_end_).count(), last_write_s_)) return;
  write_bank(path_, done);
  last_end_ = std::chrono::steady_clock::now();
  last_write_s_ = std::chrono::duration<double>(last_end_ - t).count();
  saved_ = done.materials.size();
}

}  // namespace icobrdf
