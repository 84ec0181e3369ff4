#pragma once
// The outputs of `icobrdf bench sweep` from a SweepResult (icobrdf/lab/sweep_measure.hpp):
//   RESULTS.h5     schema "icobrdf-sweep" 1.0 (docs/file-format.md, section "Sweep results"), written atomically
//   report.md      machine, command, the table, supported orders, Pareto fronts, figures, report sections
//   PNG figures    sweep_error_<model>.png (relative L2 error vs order, one series per level),
//                  sweep_pareto.png (projection time vs error, Pareto front per model),
//                  sweep_gram.png (Gram error vs order, one series per level, with the tolerance)
//   JSON           the same content, machine-readable
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "icobrdf/lab/sweep_measure.hpp"

namespace icobrdf::lab::sweep {

inline constexpr const char* kSweepFormat = "icobrdf-sweep";
inline constexpr const char* kSweepFormatVersion = "1.0";

// A file-name-safe form of a model spec: "ggx:alpha=0.05" -> "ggx_alpha_0.05".
std::string model_slug(const std::string& spec);

// Draws the sweep's figures into `dir` (an existing folder); returns their file names.
std::vector<std::string> draw_figures(const SweepResult& r, const std::string& dir);

// report.md's text; `figures` are the sweep's own figure file names (sections list theirs).
std::string report_markdown(const SweepResult& r, const std::vector<std::string>& figures);

nlohmann::json to_json(const SweepResult& r);

// What `bench sweep` prints after writing RESULTS.h5 at `output` and report.md at `report_md` with the sweep's
// `figures`: to_json plus output, report and figures; or the text, one line of pairs x models and seconds,
// one per level with the largest order it supports, one naming the files.
nlohmann::json sweep_summary_json(const SweepResult& r, const std::string& output, const std::string& report_md,
                                  const std::vector<std::string>& figures);
std::string sweep_summary_text(const SweepResult& r, const std::string& output, const std::string& report_md,
                               const std::vector<std::string>& figures);

// Writes RESULTS.h5 at `path` atomically (icobrdf/io/atomic_write.hpp): a reader sees the old file or the whole new one.
void write_results_h5(const SweepResult& r, const std::string& path);

}  // namespace icobrdf::lab::sweep
