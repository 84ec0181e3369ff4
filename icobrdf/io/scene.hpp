#pragma once
// Scenes: the TOML files that list the materials of a LUT bank (`icobrdf bank build SCENE.toml`).
//
//   [bank]                              all keys optional
//   level = 4                           grid level of the bank's /grid and /basis operators
//   levels = [3, 4, 5]                  tessellation levels tried for fitting, smallest first
//   order_max = 16                      largest expansion order tried
//   target = 0.02                       default accuracy target (relative L2 error, see below)
//   metric = "cosine"                   default error metric: "cosine" (the default) or "f" (see below)
//   sampling = "centre"                 LUT sampling during fits: "centre" or "average" (cell cubature)
//   store_lut = false                   store each material's reconstructed LUT on the bank grid
//   lut_float32 = true                  ... as float32 (its rounding error is recorded)
//   holdout_pairs = 4096                direction pairs used to measure errors (never used in fitting)
//   max_bytes, on_miss                  every material's default (as below)
//   representations = ["modes", "half-angle", "hybrid"]   what the builder may choose from, per material the
//                                       fewest bytes meeting the target (docs/glossy.md); default all three
//
//   [[material]]                        one table per material
//   name = "glossy"                     [A-Za-z0-9_-], unique
//   source = "model:ggx:alpha=0.3"      any SOURCE (icobrdf/io/brdf_source.hpp)
//   target = 0.01                       relative L2 error over the direction pairs the scene uses
//   metric = "cosine"                   "cosine": error of f cos(theta_i) cos(theta_r); "f": of f itself
//   isotropic = "auto"                  "auto" (from the measured anisotropy), true or false
//   order = 8                           fix the order instead of searching (required for delta BRDFs)
//   level = 4                           fix the fitting level instead of searching
//   incidence = [0, 75]                 incidence range the scene uses [deg]; errors measured there only
//   lights = [[30, 0], [60, 90]]        (theta, phi) [deg] of the scene's lights: errors over lights x cameras
//   cameras = [[0, 0], [45, 180]]       theta in [0, 90], |phi| <= 720; under the cosine metric not every
//                                       light (nor every camera) at theta = 90, where every weight is 0
//   prune = true                        drop negligible coefficients while the target holds
//   max_bytes = 4096                    largest size of the material's representation [bytes] (default: none)
//   on_miss = "fail"                    a target not met within max_bytes: "fail" (no bank is written) or
//                                       "keep-best": the lowest error within max_bytes is written with
//                                       target_met = false (the build exits 7; see below)
//   reciprocal = true                   judge against the data's reciprocal part (f + f^T)/2 (see below); false:
//                                       against the raw data (to reproduce a non-reciprocal measurement)
//
// Relative L2 error: sqrt(sum w^2 (f_fit - f)^2 / sum w^2 f^2) over the held-out pairs, w = 1 ("f") or
// cos(theta_i) cos(theta_r) ("cosine": reflected radiance per irradiance, as rendering weighs it): uniform in solid angle on
// both hemispheres (within the incidence range), or every light x camera pair when both sets are given.
// "cosine" is the default: a renderer multiplies f by cos(theta_i) (irradiance) and integrates over the
// projected solid angle, so it never sees the grazing growth of f that dominates the "f" metric (GGX alpha 0.3
// at target 0.05: "f" misses it at order 16 with a best error 0.887, "cosine" meets it with 8.5 KB).
// Koenderink & van Doorn (1998) likewise expand g = f cos(theta_i). The "f" metric stays available; its
// report gives the share of the reference norm from pairs beyond 80 degrees (MaterialReport::grazing_share).
// Reciprocity (Koenderink & van Doorn 1998, section 2B: "the closest function that fits the data yet respects
// reciprocity in the least-squares sense"): every representation is reciprocal, while measured data are not
// exactly. For a source not reciprocal by construction the held-out reference is the reciprocal part
// (f(w_i, w_r) + f(w_r, w_i)) / 2, and the data's own asymmetry, the metric-weighted relative L2 of
// f - (f + f^T)/2 over the held-out pairs, is reported beside the error: against the raw data no reciprocal
// representation can come closer than it (icobrdf/pipeline/held_out.hpp says how samples are judged).
// [bank] reciprocal sets every material's default.
// Budgets: the builder keeps the candidate with the fewest bytes meeting the target among those within
// max_bytes. When none does, it minimizes the error within max_bytes: every order of every level tried,
// isotropic or not as the material allows, each with as many of its largest coefficients as the budget holds
// (icobrdf/pipeline/modes_representation.hpp fit_modes_within_budget). With on_miss = "keep-best" that candidate is
// written, its target_met false, and no material is lost; with "fail" the material fails naming the lowest
// error within the budget. keep-best without max_bytes keeps the lowest error at any size.
// Errors in a scene are InputError naming the file, the material and the key.
#include <string>
#include <vector>

#include "icobrdf/core/projection/lut.hpp"

namespace icobrdf {

// Most direction pairs a material's error is measured on: holdout_pairs, and lights x cameras. A million
// pairs is 1e6 evaluations per candidate (well under a second) and ~100 MB of pair data; 1e8 would be 10 GB.
inline constexpr long long kMaxErrorPairs = 1000000;

// The scene's words, parsed once by read_scene; to_string gives back the scene's text (resume keys use it).
enum class ErrorMetric { F, Cosine };                 // "f" | "cosine"
enum class IsotropicChoice { Auto, Always, Never };   // "auto" | true | false
enum class OnMiss { Fail, KeepBest };                 // "fail" | "keep-best"
std::string to_string(ErrorMetric metric);
std::string to_string(IsotropicChoice choice);        // "auto", "true", "false"
std::string to_string(OnMiss on_miss);                // "fail", "keep-best"
std::string to_string(LutSampling sampling);          // "average", "centre"

struct SceneMaterial {
  std::string name, source;
  double target = 0.02;
  ErrorMetric metric = ErrorMetric::Cosine;
  IsotropicChoice isotropic = IsotropicChoice::Auto;
  int order = -1, level = -1;      // -1: search
  double incidence_min = 0.0, incidence_max = 90.0;  // degrees
  std::vector<std::pair<double, double>> lights, cameras;  // (theta, phi) degrees
  bool prune = true;
  bool reciprocal = true;  // judged against the reciprocal part of the data
  long long max_bytes = -1;  // -1: no budget
  OnMiss on_miss = OnMiss::Fail;
};

struct Scene {
  std::string path;
  int level = 4;
  std::vector<int> levels{3, 4, 5};
  int order_max = 16;
  double target = 0.02;
  ErrorMetric metric = ErrorMetric::Cosine;
  LutSampling sampling = LutSampling::CellCentre;  // "centre": one point per cell; "average": cell cubature
  bool store_lut = false;
  bool lut_float32 = true;
  int holdout_pairs = 4096;
  bool reciprocal = true;  // every material's default
  long long max_bytes = -1;        // every material's default; -1: no budget
  OnMiss on_miss = OnMiss::Fail;   // every material's default
  // Representations the builder may choose from, per material the one with the fewest bytes meeting the
  // target: "modes", "half-angle", "hybrid" (icobrdf/pipeline/material_candidate.hpp).
  std::vector<std::string> representations{"modes", "half-angle", "hybrid"};
  std::vector<SceneMaterial> materials;
};

Scene read_scene(const std::string& path);

}  // namespace icobrdf
