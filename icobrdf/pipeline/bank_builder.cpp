#include "icobrdf/pipeline/bank_builder.hpp"

#include <unistd.h>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <thread>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/output_path.hpp"
#include "icobrdf/pipeline/bank_assembly.hpp"
#include "icobrdf/pipeline/bank_resume.hpp"
#include "icobrdf/pipeline/held_out.hpp"
#include "icobrdf/pipeline/bank_candidates.hpp"
#include "icobrdf/pipeline/material_candidate.hpp"
#include "icobrdf/pipeline/memo_source.hpp"
#include "icobrdf/pipeline/reflectance_check.hpp"
#include "icobrdf/pipeline/resource_estimate.hpp"
#include "icobrdf/core/support/memory_budget.hpp"
#include "icobrdf/io/spectrum_file.hpp"

namespace icobrdf {
namespace {

// An asymmetry up to this is the rounding of a source reciprocal in exact arithmetic, not the data's: such a
// source is fitted as it is.
constexpr double kRoundingAsymmetry = 1e-12;

using Say = std::function<void(const std::string&)>;

std::string three_digits(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

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
  rep.target_met = c.target_met;
  rep.lobe_floor = c.target_met ? std::nan("") : c.lobe_floor;
  explain_miss(c, rep);
}

// One material from its source: held-out pairs, the best representation, the record as stored.
MaterialRecord fit_material(const Scene& scene, const SceneMaterial& m, FitContexts& contexts, BankOperators& bank,
                            MaterialReport& rep, const Say& say, const BankBuildOptions& opt, std::ostream& warnings) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto src = open_source(m.source);
  rep.source = src->spec();
  rep.target = m.target;
  rep.max_bytes = m.max_bytes;
  rep.metric = to_string(m.metric);
  std::optional<HeldOutSplit> held;
  std::optional<HeldOutErrors> errors;
  if (!src->has_delta()) {
    held = held_out_split(scene, m, *src);
    errors.emplace(held->pairs, m.order >= 0 ? m.order : scene.order_max, m.metric, held->reciprocal_reference);
    rep.grazing_share = errors->grazing_share();
    rep.asymmetry = held->asymmetry;
    rep.noise = held->noise;
    if (std::isfinite(held->noise)) say(m.name + ": the data's noise " + three_digits(held->noise) + " (from differences along its own grid)");
    rep.reciprocal_reference = held->reciprocal_reference;
    if (held->asymmetry > 0)
      say(m.name + ": the data's own asymmetry " + three_digits(held->asymmetry) + "; errors against " +
          (held->reciprocal_reference ? "their reciprocal part (f + f^T)/2" : "the raw data"));
    if (held->training)
      say(m.name + ": " + std::to_string(held->pairs.wi.rows()) + " measured sample(s) held out, the fits use the rest");
  }
  // Sources of samples are fitted on the samples not held out.
  const BrdfSource& training = held && held->training ? *held->training : *src;
  // A source slow to evaluate is evaluated once per batch of pairs its fits ask for (lobe grids, peak pairs).
  // A measurement judged against its reciprocal part is fitted to that part (pipeline/memo_source.hpp).
  std::optional<MemoSource> memo;
  const bool fit_reciprocal_part = held && held->reciprocal_reference && held->asymmetry > kRoundingAsymmetry && !training.values_only_at_samples();
  if (fit_reciprocal_part) {
    memo.emplace(training, MemoSource::ReciprocalPart{});
    say(m.name + ": the fits take the data's reciprocal part (f + f^T)/2");
  } else if (training.slow_to_evaluate()) {
    memo.emplace(training);
  }
  const BrdfSource& fitted = memo ? static_cast<const BrdfSource&>(*memo) : training;
  MaterialProblem problem{scene, m, fitted, errors ? &*errors : nullptr, contexts, say};
  std::vector<CandidatePoint> tried;  // every (bytes, error) reached: the label `candidates` (bank_candidates.hpp)
  problem.tried = &tried;
  MaterialCandidate chosen = [&] {
    try {
      return choose_representation(problem);
    } catch (const UnsupportedError& e) {
      if (!held || held->reciprocal_reference || !(held->asymmetry > m.target)) throw;
      throw UnsupportedError(std::string(e.what()) + "; the data's own asymmetry " + three_digits(held->asymmetry) +
                             " exceeds the target: against the raw data (reciprocal = false) no reciprocal representation comes closer");
    }
  }();
  report_candidate(chosen, rep);
  chosen.record.name = m.name;
  chosen.record.spectrum.source = rep.source;
  chosen.record.spectrum.channel_names = src->channel_names();  // whatever representation made the record
  MaterialRecord rec = bank.finish_record(std::move(chosen));
  if (opt.strict || opt.warnings)
    check_fitted_albedo(rec.spectrum, bank.grid(), "material '" + m.name + "' (" + quoted_text(rep.source) + ")",
                        {opt.strict, &warnings});
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  store_choice(rec, rep);
  if (!tried.empty()) rec.labels[kCandidatesLabel] = candidates_text(std::move(tried));
  return rec;
}

}  // namespace

void explain_miss(const MaterialCandidate& c, MaterialReport& rep) {
  if (rep.target_met || !rep.measured) return;
  std::string note = c.note;
  const double asym = rep.asymmetry;
  if (std::isfinite(asym) && asym > 0) {
    const bool within = rep.error_l2 <= kNoiseMargin * asym;
    rep.below_noise = within;
    note += std::string(note.empty() ? "" : "; ") + "the data's asymmetry " + three_digits(asym) +
            (within ? ": the error is within it" : ": the error is above it, the representation's own floor");
    // Against the raw data no reciprocal representation comes below the asymmetry. Against the reciprocal part
    // it is only a noise estimate, not a floor: lobes fitted to that part reach below it (benchmarks/RESULTS.md).
    if (within) note += rep.reciprocal_reference ? " (a noise estimate, not a floor)" : ", which no reciprocal representation comes below";
  }
  // The noise along the data's own grid (icobrdf/pipeline/held_out.hpp): an error within it is the data's noise.
  if (std::isfinite(rep.noise) && rep.noise > 0) {
    const bool within = rep.error_l2 <= kNoiseMargin * rep.noise;
    rep.below_noise = rep.below_noise || within;
    note += std::string(note.empty() ? "" : "; ") + "the data's noise " + three_digits(rep.noise) +
            (within ? ": the error is within it" : ": the error is above it");
  }
  rep.note = note;
}

MaterialFitter::MaterialFitter(const Scene& scene, const BankBuildOptions& opt)
    : scene_(scene), options_(opt), contexts_(std::make_unique<FitContexts>()), bank_(std::make_unique<BankOperators>(scene)) {}

MaterialFitter::~MaterialFitter() = default;

void MaterialFitter::say(const std::string& line) {
  if (!options_.progress) return;
  std::lock_guard<std::mutex> g(output_lock_);
  options_.progress(line);
}

MaterialRecord MaterialFitter::fit(std::size_t index, MaterialReport& rep) {
  const Say say = [this](const std::string& line) { this->say(line); };
  // Warnings are gathered and passed on whole, after the fit.
  std::ostringstream warnings;
  const auto pass_on = [&] {
    if (warnings.tellp() <= 0) return;
    std::lock_guard<std::mutex> g(output_lock_);
    *(options_.warnings ? options_.warnings : &std::cerr) << warnings.str() << std::flush;
  };
  try {
    MaterialRecord rec = fit_material(scene_, scene_.materials.at(index), *contexts_, *bank_, rep, say, options_, warnings);
    pass_on();
    return rec;
  } catch (...) {
    pass_on();
    throw;
  }
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

MaterialsAtOnce plan_materials_at_once(const Scene& scene, const std::vector<std::size_t>& todo, int threads, int requested) {
  if (requested < 0) throw ArgumentError("bank build: materials at once = " + std::to_string(requested) + ", expected >= 0 (0 chooses)");
  MaterialsAtOnce plan;
  threads = std::max(1, threads);
  int channels = 1;
  double bytes = 0.0;  // the largest small fit's peak, on one thread
  for (const std::size_t i : todo) {
    const SceneMaterial& m = scene.materials.at(i);
    const int level = m.level >= 0 ? m.level : *std::max_element(scene.levels.begin(), scene.levels.end());
    const int order = m.order >= 0 ? m.order : scene.order_max;
    if (static_cast<double>(equal_area_cells(level)) <= kConcurrentFitMaxCells) {
      plan.at_once.push_back(i);
      bytes = std::max(bytes, model_fit_bytes(level, order, channels, 1));
    } else {
      plan.alone.push_back(i);
    }
  }
  int w = requested;
  if (w == 0) {
    w = threads;
    if (bytes > 0.0) w = std::min(w, static_cast<int>(std::max(1.0, 0.5 * available_memory().bytes / bytes)));
  }
  w = std::min<int>(w, static_cast<int>(plan.at_once.size()));
  if (w <= 1) {  // every material in turn on all threads
    plan.alone = todo;
    plan.at_once.clear();
    plan.workers = 1;
    plan.threads_each = threads;
    return plan;
  }
  plan.workers = w;
  plan.threads_each = std::max(1, threads / w);
  return plan;
}

namespace {

// One material's outcome from a fitting thread.
struct Fitted {
  std::size_t index = 0;
  MaterialReport report;
  std::optional<MaterialRecord> record;  // empty: failed with `error`
  std::string error;
};

// The materials of plan.at_once fitted plan.workers at a time; each outcome goes to `out` on this thread, as
// it arrives. Returns whether a stop left materials unfitted.
bool fit_at_once(const Scene& scene, const BankBuildOptions& opt, const MaterialsAtOnce& plan, MaterialFitter& fitter,
                 BankCollector& out, const std::function<void(std::size_t)>& say_start) {
  std::mutex lock;
  std::condition_variable arrived;
  std::size_t next = 0;
  int running = plan.workers;
  bool stopped = false;
  std::deque<Fitted> inbox;
  const auto work = [&] {
    omp_set_num_threads(plan.threads_each);  // this thread's OpenMP teams (and Eigen's products, which follow them)
    for (;;) {
      Fitted f;
      {
        std::lock_guard<std::mutex> g(lock);
        if (next == plan.at_once.size()) break;
        if (opt.stop && opt.stop->load() != 0) {
          stopped = true;
          break;
        }
        f.index = plan.at_once[next++];
        say_start(f.index);
      }
      f.report = new_material_report(scene, f.index);
      try {
        f.record = fitter.fit(f.index, f.report);
      } catch (const std::exception& e) {
        f.error = e.what();
      } catch (...) {
        f.error = "unknown error";
      }
      {
        std::lock_guard<std::mutex> g(lock);
        inbox.push_back(std::move(f));
      }
      arrived.notify_one();
    }
    {
      std::lock_guard<std::mutex> g(lock);
      --running;
    }
    arrived.notify_one();
  };
  std::vector<std::thread> threads;
  const auto join = [&] {
    for (auto& t : threads)
      if (t.joinable()) t.join();
  };
  try {
    for (int w = 0; w < plan.workers; ++w) threads.emplace_back(work);
    for (;;) {
      std::unique_lock<std::mutex> g(lock);
      arrived.wait(g, [&] { return !inbox.empty() || running == 0; });
      if (inbox.empty()) break;
      Fitted f = std::move(inbox.front());
      inbox.pop_front();
      g.unlock();
      if (f.record)
        out.finished(f.index, std::move(*f.record), std::move(f.report));
      else
        out.failed(f.index, std::move(f.report), f.error);
    }
  } catch (...) {  // the collector failed: no new material starts, the running ones end, the error goes up
    {
      std::lock_guard<std::mutex> g(lock);
      next = plan.at_once.size();
    }
    join();
    throw;
  }
  join();
  return stopped;
}

}  // namespace

BankBuildResult build_bank(const Scene& scene, const BankBuildOptions& opt) {
  BankCollector out(scene, opt);
  MaterialFitter fitter(scene, opt);
  std::size_t started = 0;
  const auto say_start = [&](std::size_t i) {  // through the fitter: one line at a time with the fits' own lines
    const auto& m = scene.materials[i];
    fitter.say("[" + std::to_string(++started) + "/" + std::to_string(scene.materials.size()) + "] " + m.name + " (" + quoted_text(m.source) + ")");
  };
  const auto stopped = [&] { return opt.stop && opt.stop->load() != 0; };
  // Materials of the resume file first, in scene order; then the plan.
  std::vector<std::size_t> todo;
  for (std::size_t i = 0; i < scene.materials.size(); ++i) {
    try {
      if (out.take_resumed(i)) {
        say_start(i);
        continue;
      }
    } catch (const std::exception& e) {  // the record could not be taken: the material fails, as a fit would
      out.failed(i, new_material_report(scene, i), e.what());
      continue;
    }
    todo.push_back(i);
  }
  bool interrupted = false;
  const MaterialsAtOnce plan = plan_materials_at_once(scene, todo, omp_get_max_threads(), opt.materials_at_once);
  for (const std::size_t i : plan.alone) {
    if (stopped()) {
      interrupted = true;
      break;
    }
    say_start(i);
    MaterialReport rep = new_material_report(scene, i);
    try {
      MaterialRecord rec = fitter.fit(i, rep);
      out.finished(i, std::move(rec), std::move(rep));
    } catch (const std::exception& e) {
      out.failed(i, std::move(rep), e.what());
    }
  }
  if (!interrupted && !plan.at_once.empty()) interrupted = fit_at_once(scene, opt, plan, fitter, out, say_start);
  return out.finish(fitter.operators(), interrupted);
}

std::string kept_for_resume(const BankBuildResult& r) {
  if (r.resume_file.empty()) return "no material finished, nothing kept for --resume";
  return std::to_string(r.resume_materials) + " finished material(s) kept in " + r.resume_file + " (use --resume)";
}

}  // namespace icobrdf
