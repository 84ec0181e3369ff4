#include "icobrdf/pipeline/bank_builder.hpp"

#include <unistd.h>

#include <chrono>
#include <iostream>
#include <map>
#include <optional>

#include "icobrdf/core/error.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/output_path.hpp"
#include "icobrdf/pipeline/bank_assembly.hpp"
#include "icobrdf/pipeline/bank_resume.hpp"
#include "icobrdf/pipeline/held_out.hpp"
#include "icobrdf/pipeline/material_candidate.hpp"
#include "icobrdf/pipeline/reflectance_check.hpp"

namespace icobrdf {
namespace {

using Say = std::function<void(const std::string&)>;

void report_candidate(const MaterialCandidate& c, MaterialReport& rep) {
  rep.representation = c.representation;
  rep.isotropic = c.isotropic;
  rep.measured = c.measured;
  rep.level = c.level;
  rep.order = c.order;
  rep.error_l2 = c.error.l2;
  rep.error_max = c.error.max;
  rep.anisotropy = c.anisotropy;
  rep.kept = c.kept;
  rep.total = c.total;
  rep.bytes = c.bytes;
}

// One material from its source: held-out pairs, the best representation, the record as stored.
MaterialRecord fit_material(const Scene& scene, const SceneMaterial& m, FitContexts& contexts, BankOperators& bank,
                            MaterialReport& rep, const Say& say, const BankBuildOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto src = open_source(m.source);
  rep.source = src->spec();
  rep.target = m.target;
  std::optional<HeldOutSplit> held;
  std::optional<HeldOutErrors> errors;
  if (!src->has_delta()) {
    held = held_out_split(scene, m, *src);
    errors.emplace(held->pairs, m.order >= 0 ? m.order : scene.order_max, m.metric);
    if (held->training)
      say(m.name + ": " + std::to_string(held->pairs.wi.rows()) + " measured sample(s) held out, the fits use the rest");
  }
  // Sources of samples are fitted on the samples not held out.
  const BrdfSource& fitted = held && held->training ? *held->training : *src;
  const MaterialProblem problem{scene, m, fitted, errors ? &*errors : nullptr, contexts, say};
  MaterialCandidate chosen = choose_representation(problem);
  report_candidate(chosen, rep);
  chosen.record.name = m.name;
  chosen.record.spectrum.source = rep.source;
  chosen.record.spectrum.channel_names = src->channel_names();  // whatever representation made the record
  MaterialRecord rec = bank.finish_record(std::move(chosen));
  if (opt.strict || opt.warnings)
    check_fitted_albedo(rec.spectrum, bank.grid(), "material '" + m.name + "' (" + quoted_text(rep.source) + ")",
                        {opt.strict, opt.warnings ? opt.warnings : &std::cerr});
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  store_choice(rec, rep);
  return rec;
}

// A material taken from the resume file or fitted; its report is filled in either way.
MaterialRecord material_record(const Scene& scene, const SceneMaterial& m, const std::map<std::string, MaterialRecord>& previous,
                               FitContexts& contexts, BankOperators& bank, MaterialReport& rep, const Say& say,
                               const BankBuildOptions& opt) {
  const auto prev = previous.find(rep.key);
  if (prev == previous.end()) return fit_material(scene, m, contexts, bank, rep, say, opt);
  MaterialRecord rec = prev->second;
  rec.name = m.name;
  report_from_record(rec, rep);
  return rec;
}

}  // namespace

BankBuildResult build_bank(const Scene& scene, const BankBuildOptions& opt) {
  if (opt.output.empty()) throw ArgumentError("bank build: an output path is required");
  const Say say = [&](const std::string& line) {
    if (opt.progress) opt.progress(line);
  };
  const std::string partial_path = opt.output + ".partial";
  std::vector<std::string> inputs{scene.path};
  for (const auto& m : scene.materials) inputs.push_back(m.source);
  check_output_path(opt.output, inputs);  // before any work, the resume file read included
  check_output_path(partial_path, inputs);
  std::map<std::string, MaterialRecord> previous;  // key -> record
  if (opt.resume) {
    if (auto found = read_resume_file(partial_path)) {
      previous = std::move(*found);
      say("resuming: " + std::to_string(previous.size()) + " finished material(s) in " + partial_path);
    }
  }
  FitContexts contexts;
  BankOperators bank(scene);
  BankBuildResult result;
  BankContents done;  // finished materials, in scene order
  bool failed = false;
  Checkpointer checkpoint(partial_path);
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    const auto& m = scene.materials[i];
    if (opt.stop && opt.stop->load() != 0) {
      result.interrupted = true;
      break;
    }
    MaterialReport rep;
    rep.name = m.name;
    rep.key = material_key(scene, m);
    say("[" + std::to_string(i + 1) + "/" + std::to_string(scene.materials.size()) + "] " + m.name + " (" + quoted_text(m.source) + ")");
    try {
      done.materials.push_back(material_record(scene, m, previous, contexts, bank, rep, say, opt));
      rep.ok = true;
      checkpoint.maybe_write(done, false);
    } catch (const std::exception& e) {
      rep.ok = false;
      rep.error = e.what();
      failed = true;
      say(m.name + ": FAILED: " + rep.error);
    }
    result.materials.push_back(std::move(rep));
  }
  if (failed || result.interrupted) {
    checkpoint.maybe_write(done, true);  // every finished material is kept for --resume
    result.resume_materials = checkpoint.saved();
    if (result.resume_materials > 0) result.resume_file = partial_path;
    return result;
  }
  write_bank(opt.output, assemble_bank(bank, std::move(done.materials)));
  ::unlink(partial_path.c_str());
  result.written = true;
  return result;
}

std::string kept_for_resume(const BankBuildResult& r) {
  if (r.resume_file.empty()) return "no material finished, nothing kept for --resume";
  return std::to_string(r.resume_materials) + " finished material(s) kept in " + r.resume_file + " (use --resume)";
}

}  // namespace icobrdf
