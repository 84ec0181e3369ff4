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
// A material whose target cannot be met, or whose source fails, is reported with its reason; the build then
// fails as a whole (no bank is written) while the finished materials stay in the resume file.
//
// Both output paths, the bank and its resume file OUTPUT.partial, are checked before any work
// (icobrdf/io/output_path.hpp): a folder, FIFO, device or link there, a missing or unwritable folder, or an output
// that is one of the build's inputs (the scene, a material's source file) fails at once.
// The bank is written atomically at the end and the resume file OUTPUT.partial (icobrdf/pipeline/bank_resume.hpp)
// removed.
#include <atomic>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "icobrdf/io/scene.hpp"

namespace icobrdf {

struct MaterialReport {
  std::string name, source, key;
  bool ok = false;
  std::string error;           // why it failed (ok = false)
  bool resumed = false;        // taken from the resume file
  std::string representation;  // "modes", "half-angle" or "hybrid" (icobrdf/pipeline/material_candidate.hpp)
  bool isotropic = false;
  bool measured = true;        // false for delta BRDFs
  int level = -1, order = -1;  // fitting level and order of the modes; -1 for a lobe alone
  double target = 0.0;
  double error_l2 = 0.0;       // relative L2 over the held-out pairs
  double error_max = 0.0;      // max |f_fit - f| / max |f| over the held-out pairs
  double anisotropy = 0.0;     // anisotropic energy fraction of the first fit
  int kept = 0, total = 0;     // coefficients kept after pruning / in the full (B|IB)SSS vector
  long long bytes = 0;         // kept coefficients (8 bytes per channel) and their indices (4 bytes each)
  double seconds = 0.0;
};

struct BankBuildOptions {
  std::string output;
  bool resume = false;
  std::function<void(const std::string&)> progress;  // one line per step, may be empty
  const std::atomic<int>* stop = nullptr;             // non-zero: stop after the current material
  // Negative directional albedo of a fitted material (icobrdf/pipeline/reflectance_check.hpp): a warning on
  // `warnings` (none when null), or, when strict, the material fails.
  bool strict = false;
  std::ostream* warnings = nullptr;
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

// What a failed or interrupted build kept for --resume, for its message: "N finished material(s) kept in
// OUTPUT.partial (use --resume)", naming the file only when this build wrote it, else "no material
// finished, nothing kept for --resume".
std::string kept_for_resume(const BankBuildResult& result);

}  // namespace icobrdf
