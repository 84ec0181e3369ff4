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

}  // namespace

MaterialFitter::MaterialFitter(const Scene& scene, const BankBuildOptions& opt)
    : scene_(scene), options_(opt), contexts_(std::make_unique<FitContexts>()), bank_(std::make_unique<BankOperators>(scene)) {}

MaterialFitter::~MaterialFitter() = default;

MaterialRecord MaterialFitter::fit(std::size_t index, MaterialReport& rep) {
  const Say say = [this](const std::string& line) {
    if (options_.progress) options_.progress(line);
  };
  return fit_material(scene_, scene_.materials.at(index), *contexts_, *bank_, rep, say, options_);
}

BankCollector::BankCollector(const Scene& scene, const BankBuildOptions& opt)
    : scene_(scene), options_(opt), partial_path_(opt.output + ".partial"), reports_(scene.materials.size()) {
  if (opt.output.empty()) throw ArgumentError("bank build: an output path is required");
  std::vector<std::string> inputs{scene.path};
  for (const auto& m : scene.materials) inputs.push_back(m.source);
  check_output_path(opt.output, inputs);  // before any work, the resume file read included
  check_output_path(partial_path_, inputs);
  if (opt.resume) {
    if (auto found = read_resume_file(partial_path_)) {
      previous_ = std::move(*found);
      if (opt.progress) opt.progress("resuming: " + std::to_string(previous_.size()) + " finished material(s) in " + partial_path_);
    }
  }
  checkpoint_ = std::make_unique<Checkpointer>(partial_path_);
  done_at_.assign(scene.materials.size(), -1);
  writer_ = std::make_unique<BankWriter>(opt.output);
}

BankCollector::~BankCollector() = default;

MaterialReport new_material_report(const Scene& scene, std::size_t index) {
  MaterialReport rep;
  rep.name = scene.materials.at(index).name;
  rep.key = material_key(scene, scene.materials[index]);
  return rep;
}

bool BankCollector::take_resumed(std::size_t index) {
  MaterialReport rep = new_material_report(scene_, index);
  const auto prev = previous_.find(rep.key);
  if (prev == previous_.end()) return false;
  MaterialRecord rec = prev->second;
  rec.name = rep.name;
  report_from_record(rec, rep);
  finished(index, std::move(rec), std::move(rep));
  return true;
}

void BankCollector::finished(std::size_t index, MaterialRecord record, MaterialReport report) {
  report.ok = true;
  done_at_.at(index) = static_cast<std::ptrdiff_t>(done_.materials.size());
  done_.materials.push_back(std::move(record));
  reports_.at(index) = std::move(report);
  write_ready();
  checkpoint_->maybe_write(done_, false);
}

// The finished materials next in scene order go into the bank (none once a material failed: no bank then).
void BankCollector::write_ready() {
  if (!writer_ || failed_) return;
  try {
    while (written_ < done_at_.size() && done_at_[written_] >= 0) {
      writer_->add(done_.materials[static_cast<std::size_t>(done_at_[written_])]);
      ++written_;
    }
  } catch (...) {
    write_error_ = std::current_exception();
    writer_.reset();
  }
}

void BankCollector::failed(std::size_t index, MaterialReport report, const std::string& error) {
  report.ok = false;
  report.error = error;
  failed_ = true;
  if (options_.progress) options_.progress(report.name + ": FAILED: " + error);
  reports_.at(index) = std::move(report);
}

BankBuildResult BankCollector::finish(BankOperators& operators, bool interrupted) {
  BankBuildResult result;
  result.interrupted = interrupted;
  for (auto& r : reports_)
    if (r) result.materials.push_back(std::move(*r));
  if (failed_ || interrupted || done_.materials.size() != scene_.materials.size() || write_error_) {
    writer_.reset();                        // no bank: its temporary goes
    checkpoint_->maybe_write(done_, true);  // every finished material is kept for --resume
    result.resume_materials = checkpoint_->saved();
    if (result.resume_materials > 0) result.resume_file = partial_path_;
    if (write_error_ && !failed_ && !interrupted) std::rethrow_exception(write_error_);
    return result;
  }
  std::vector<int> orders;
  for (const auto& rec : done_.materials) orders.push_back(rec.spectrum.order);
  try {
    writer_->finish(bank_operators_part(operators, std::move(orders)));
  } catch (...) {
    writer_.reset();
    checkpoint_->maybe_write(done_, true);
    throw;
  }
  writer_.reset();
  ::unlink(partial_path_.c_str());
  result.written = true;
  return result;
}

BankBuildResult build_bank(const Scene& scene, const BankBuildOptions& opt) {
  BankCollector out(scene, opt);
  MaterialFitter fitter(scene, opt);
  bool interrupted = false;
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    const auto& m = scene.materials[i];
    if (opt.stop && opt.stop->load() != 0) {
      interrupted = true;
      break;
    }
    if (opt.progress)
      opt.progress("[" + std::to_string(i + 1) + "/" + std::to_string(scene.materials.size()) + "] " + m.name + " (" + quoted_text(m.source) + ")");
    MaterialReport rep = new_material_report(scene, i);
    try {
      if (out.take_resumed(i)) continue;
      MaterialRecord rec = fitter.fit(i, rep);
      out.finished(i, std::move(rec), std::move(rep));
    } catch (const std::exception& e) {
      out.failed(i, std::move(rep), e.what());
    }
  }
  return out.finish(fitter.operators(), interrupted);
}

std::string kept_for_resume(const BankBuildResult& r) {
  if (r.resume_file.empty()) return "no material finished, nothing kept for --resume";
  return std::to_string(r.resume_materials) + " finished material(s) kept in " + r.resume_file + " (use --resume)";
}

}  // namespace icobrdf
