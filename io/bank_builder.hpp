#pragma once
// Building a LUT bank from a scene: "model only what a scene needs" (io/scene.hpp for the scene file).
//
// Per material:
//   1. held-out direction pairs (seeded by the material, never used in fitting) restricted to the
//      directions the scene uses; the reference values f come from the source itself;
//   2. isotropic or not: "auto" fits once and measures the anisotropic energy fraction a; since the basis is
//      orthonormal, dropping the anisotropic part costs a relative L2 error sqrt(a), so the material is
//      treated as isotropic when sqrt(a) <= target / 2;
//   3. the smallest (level, order): levels ascending; at each level one fit at the largest order the level
//      supports (core/discrete_basis.hpp) whose truncations give the error of every lower order; the
//      smallest order meeting the target is then fitted on its own and verified;
//   4. pruning: coefficients (BSSS, or IBSSS when isotropic) dropped smallest first while the held-out
//      error stays within the target;
//   5. the record: spectrum, IBSSS, optional LUT on the bank grid, and the choice with its figures
//      (kept coefficients, bytes, achieved errors, time).
// Materials with delta parts (ideal mirror, retroreflector) have no pointwise error: their order must be
// given (or order_max is used), and the report says the error was not measured.
// A material whose target cannot be met, or whose source fails, is reported with its reason; the build then
// fails as a whole (no bank is written) while the finished materials stay in the resume file.
//
// The bank stores its grid (level `level`) with B and G for every order used, and P where that grid supports
// the order (its Gram error is within the default tolerance); reconstruction F = B C B^T needs only B.
//
// Resume: the finished materials are written (atomically) to OUTPUT.partial, keyed by a hash of the source
// text, the material's settings and the bank settings; with `resume`, materials whose key matches are taken
// from there. The file is rewritten after the first material, then whenever the time since the last rewrite
// reaches 10 times that rewrite's duration (rewrites grow with the materials kept; this bounds them to 9% of
// the build), and at the end of a failed or interrupted build: a SIGKILL loses at most that much work. The
// bank itself is written atomically at the end and the partial file removed.
#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "io/scene.hpp"

namespace icobrdf {

struct MaterialReport {
  std::string name, source, key;
  bool ok = false;
  std::string error;           // why it failed (ok = false)
  bool resumed = false;        // taken from the resume file
  bool isotropic = false;
  bool measured = true;        // false for delta BRDFs
  int level = -1, order = -1;
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
};

struct BankBuildResult {
  std::vector<MaterialReport> materials;
  bool written = false;      // the bank was written
  bool interrupted = false;  // stopped by *stop before all materials were done
};

BankBuildResult build_bank(const Scene& scene, const BankBuildOptions& options);

// FNV-1a 64-bit hash, as 16 hex digits (resume keys).
std::string fnv1a_hex(const std::string& text);

}  // namespace icobrdf
