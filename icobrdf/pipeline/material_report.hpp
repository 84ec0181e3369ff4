#pragma once
// What a bank build reports of one material: its choice, the figures of that choice, or why it failed. The
// builder fills it (icobrdf/pipeline/bank_builder.hpp), the resume file keeps it (bank_resume.hpp), and the
// program prints it (the bank build table and JSON).
#include <limits>
#include <string>

namespace icobrdf {

// The data's noise has two estimates. Its asymmetry: when f(a, b) and f(b, a) are measured with independent
// errors of one size, the reciprocal part (f + f^T)/2 keeps noise of exactly the size of the antisymmetric part
// (f - f^T)/2, so a representation that holds the BRDF but not the noise has an error of about the asymmetry
// against the reciprocal part (an upper figure: a systematic non-reciprocity counts too). Its noise figure, from
// the differences along the data's own grid (icobrdf/pipeline/held_out.hpp `noise`). A missed target is
// explained by the noise when the error is within this factor of either: both are estimates on the held-out
// pairs, and the equalities hold in expectation only.
inline constexpr double kNoiseMargin = 1.25;

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
  std::string metric = "cosine";  // the error metric ("cosine" or "f", icobrdf/io/scene.hpp)
  double grazing_share = 0.0;
  // The data's own asymmetry over the held-out pairs (icobrdf/pipeline/held_out.hpp; 0 for sources reciprocal by
  // construction, NaN when not measurable), and whether the errors are against the data's reciprocal part.
  double asymmetry = 0.0;
  // The data's noise figure over the held-out pairs (HeldOutSplit::noise; NaN when the source has no grid).
  double noise = std::numeric_limits<double>::quiet_NaN();
  bool reciprocal_reference = false;  // share of the reference norm from grazing pairs (HeldOutErrors::grazing_share)
  double anisotropy = 0.0;     // anisotropic energy fraction of the first fit
  int kept = 0, total = 0;     // coefficients kept after pruning / in the full (B|IB)SSS vector
  long long bytes = 0;         // kept coefficients (8 bytes per channel) and their indices (4 bytes each)
  long long max_bytes = -1;    // the material's budget; -1: none
  bool target_met = true;      // false: kept as the best within the budget (on_miss = "keep-best")
  // A missed target (target_met false) explained by a measured figure: the error is within kNoiseMargin of the
  // data's noise estimate (below_noise), and `note` says where the search stopped and which figure stopped it.
  bool below_noise = false;
  std::string note;
  // The lobe search's floor within the budget (MaterialCandidate::lobe_floor): a missed target it explains by
  // a measured figure of the representation; NaN when not measured.
  double lobe_floor = std::numeric_limits<double>::quiet_NaN();
  double seconds = 0.0;
  int rank = -1;               // the MPI rank that fitted it (icobrdf/cluster/distributed_bank.hpp); -1 in one process
};

}  // namespace icobrdf
