#pragma once
// Building a LUT bank from a scene: "model only what a scene needs" (icobrdf/io/scene.hpp for the scene file,
// docs/architecture.md for the walk from `icobrdf bank build` down to the products).
//
// Per material:
//   1. held-out direction pairs, never used in fitting, restricted to the directions the scene uses; the
//      reference values f come from the source itself (icobrdf/pipeline/held_out.hpp);
//   2. one candidate per representation (icobrdf/pipeline/material_candidate.hpp), the one with the fewest bytes
//      meeting the target kept. The "modes" representation (icobrdf/pipeline/modes_representation.hpp) searches the
//      smallest (level, order) (icobrdf/pipeline/level_order_search.hpp), makes the spectrum isotropic when the
//      scene allows it and its isotropic projection still meets the target, and prunes coefficients while
//      the target holds (icobrdf/pipeline/pruning.hpp);
//   3. the record: spectrum, IBSSS, optional LUT on the bank grid, and the choice with its figures
//      (kept coefficients, bytes, achieved errors, time) (icobrdf/pipeline/bank_assembly.hpp).
// Materials with delta parts (ideal mirror, retroreflector) have no pointwise error: their order must be
// given (or order_max is used), and the report says the error was not measured.
// A material whose target cannot be met within its max_bytes, or whose source fails, is reported with its
// reason; the build then fails as a whole (no bank is written) while the finished materials stay in the
// resume file. With on_miss = "keep-best" (icobrdf/io/scene.hpp) a missed target is not a failure: the lowest
// error within the budget is written with target_met = false (MaterialReport), beside every other material.
//
// Both output paths, the bank and its resume file OUTPUT.partial, are checked before any work
// (icobrdf/io/output_path.hpp): a folder, FIFO, device or link there, a missing or unwritable folder, or an output
// that is one of the build's inputs (the scene, a material's source file) fails at once.
// The bank is written atomically at the end and the resume file OUTPUT.partial (icobrdf/pipeline/bank_resume.hpp)
// removed.
#include <atomic>
#include <cstddef>
#include <functional>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/scene.hpp"
#include "icobrdf/pipeline/material_report.hpp"

namespace icobrdf {

struct MaterialCandidate;  // icobrdf/pipeline/material_problem.hpp

struct BankBuildOptions {
  std::string output;
  bool resume = false;
  std::function<void(const std::string&)> progress;  // one line per step, may be empty
  const std::atomic<int>* stop = nullptr;             // non-zero: stop after the current material
  // Negative directional albedo of a fitted material (icobrdf/pipeline/reflectance_check.hpp): a warning on
  // `warnings` (none when null), or, when strict, the material fails.
  bool strict = false;
  std::ostream* warnings = nullptr;
  // Materials fitted at once, each on its share of the OpenMP threads (see plan_materials_at_once): 0
  // chooses, 1 fits every material in turn on all threads, W >= 2 fits the small ones W at a time.
  int materials_at_once = 0;
};

struct BankBuildResult {
  std::vector<MaterialReport> materials;
  bool written = false;      // the bank was written
  bool interrupted = false;  // stopped by *stop before all materials were done
  // The resume file this build wrote its finished materials to, and how many it holds; "" and 0 when it
  // wrote none (no material finished) or removed it (the bank was written).
  std::string resume_file;
  std::size_t resume_materials = 0;
};

BankBuildResult build_bank(const Scene& scene, const BankBuildOptions& options);

// A measured material that missed its target (report.target_met false): report.note = the candidate's note (where
// its search stopped) and the data's noise estimates, its asymmetry and its noise figure; report.below_noise when
// the error is within kNoiseMargin of either (icobrdf/pipeline/material_report.hpp). Reads error_l2, asymmetry,
// noise, reciprocal_reference.
void explain_miss(const MaterialCandidate& candidate, MaterialReport& report);

// Fitting several materials at once. A small fit's parallel regions are short, and two threads gained only
// 1.28x on a bank of 100 level-4 materials (benchmarks/RESULTS.md), while two such materials fitted side by
// side, one thread each, take the time of one. So build_bank fits the small materials (fitting grid of at most
// kConcurrentFitMaxCells cells) W at a time on T / W threads each, after the others, which it fits in turn on
// all T threads (a large material alone on one thread would hold up the build's end).
// W = options.materials_at_once, or when that is 0: T (one thread each) when T >= 2 and at least 2 small
// materials are to be fitted, limited so that W fits at once need at most half the available memory
// (icobrdf/pipeline/resource_estimate.hpp); else 1. The bank is byte-identical whatever W is (up to the
// `seconds` figures): each material's fit does not depend on the thread count, and the bank is written in
// scene order (BankCollector).
inline constexpr double kConcurrentFitMaxCells = 3000;
struct MaterialsAtOnce {
  int workers = 1;                   // W
  int threads_each = 1;              // OpenMP threads of each
  std::vector<std::size_t> alone;    // materials fitted in turn on all threads, in scene order
  std::vector<std::size_t> at_once;  // materials fitted W at a time, in scene order
};
// The plan for the materials `todo` (scene indices) on `threads` threads.
MaterialsAtOnce plan_materials_at_once(const Scene& scene, const std::vector<std::size_t>& todo, int threads, int requested);

// The two halves of build_bank, for builds that spread the materials over processes
// (icobrdf/cluster/distributed_bank.hpp); build_bank is these two in one loop.
//
// MaterialFitter: fits material `index` of the scene (its source, held-out pairs, representation, record with
// its LUT); it keeps the fitting caches (level contexts, bank operators) from one material to the next.
// Throws what the fit throws (the material failed). `fit` may be called from several threads at once: the
// caches are locked, and progress and warning lines are passed on one whole line at a time.
// The report of material `index` of the scene with its name and key (icobrdf/pipeline/bank_resume.hpp) filled in.
MaterialReport new_material_report(const Scene& scene, std::size_t index);

class BankOperators;
class FitContexts;
class MaterialFitter {
 public:
  MaterialFitter(const Scene& scene, const BankBuildOptions& options);
  ~MaterialFitter();
  MaterialRecord fit(std::size_t index, MaterialReport& report);
  // Passes a progress line on to options.progress, one line at a time with the fits' own (any thread).
  void say(const std::string& line);
  BankOperators& operators() { return *bank_; }

 private:
  const Scene& scene_;
  const BankBuildOptions& options_;
  std::unique_ptr<FitContexts> contexts_;
  std::unique_ptr<BankOperators> bank_;
  std::mutex output_lock_;  // progress and warning lines from concurrent fits
};

// BankCollector: the writing half. Its constructor checks both output paths and reads the resume file (with
// options.resume); it then takes each material's outcome in any order and checkpoints the finished ones
// (icobrdf/pipeline/bank_resume.hpp). The bank itself is written as the build goes (icobrdf/io/bank_file.hpp
// BankWriter, to a temporary): each material as soon as it and every one before it in the scene are
// finished, so that the writing overlaps the fitting (in a distributed build, the other ranks' fitting).
// `finish` adds the grid and the operators and puts the bank in place when every material succeeded;
// otherwise the temporary is dropped. A failure to write the bank stops its writing, not the build: the
// finished materials are still checkpointed, and `finish` throws that error after the checkpoint.
class Checkpointer;
class BankCollector {
 public:
  BankCollector(const Scene& scene, const BankBuildOptions& options);
  ~BankCollector();
  std::size_t size() const { return scene_.materials.size(); }
  // True when the resume file holds the material: its record and report are then taken as finished.
  bool take_resumed(std::size_t index);
  void finished(std::size_t index, MaterialRecord record, MaterialReport report);
  void failed(std::size_t index, MaterialReport report, const std::string& error);
  // Writes the bank (every material finished, not `interrupted`) and removes the resume file, or writes
  // the resume file with every finished material. `operators` provides the bank's grid and basis.
  BankBuildResult finish(BankOperators& operators, bool interrupted);

 private:
  const Scene& scene_;
  const BankBuildOptions& options_;
  std::string partial_path_;
  std::map<std::string, MaterialRecord> previous_;  // key -> record, from the resume file
  BankContents done_;                                // finished materials, in the order they finished
  std::vector<std::optional<MaterialReport>> reports_;
  bool failed_ = false;
  std::unique_ptr<Checkpointer> checkpoint_;
  // The bank being written: materials [0, written_) of the scene are in it; done_at_[i] is material i's
  // place in done_ (-1 until finished). write_error_: the writer failed (and was dropped).
  std::unique_ptr<BankWriter> writer_;
  std::size_t written_ = 0;
  std::vector<std::ptrdiff_t> done_at_;
  std::exception_ptr write_error_;
  void write_ready();
};

// What a failed or interrupted build kept for --resume, for its message: "N finished material(s) kept in
// OUTPUT.partial (use --resume)", naming the file only when this build wrote it, else "no material
// finished, nothing kept for --resume".
std::string kept_for_resume(const BankBuildResult& result);

}  // namespace icobrdf
