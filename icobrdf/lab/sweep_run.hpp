#pragma once
// One whole speed-against-error sweep (`icobrdf bench sweep`, icobrdf/lab/sweep_measure.hpp): its model list,
// its output paths, and the run that writes RESULTS.h5 (docs/file-format.md, "Sweep results") and the report
// folder (report.md with PNG figures, icobrdf/lab/sweep_report.hpp).
//
// Nothing is written unless the whole sweep succeeds: the report is assembled in a hidden folder beside the
// report folder and moved into place at the end (report.md last, icobrdf/lab/staged_folder.hpp), RESULTS.h5 is
// written atomically; on any error both are removed and an existing RESULTS.h5 is left untouched.
//
// Messages name the caller's words for the model list and the report folder (`models_label`, `report_label`).
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "icobrdf/lab/sweep_measure.hpp"

namespace icobrdf::lab::sweep {

// Canonical specs and the labels (as given) of a model list (split_model_list; empty: default_models()).
// ArgumentError for an empty item, a model with delta parts (no pointwise error) or a model listed twice.
std::pair<std::vector<std::string>, std::vector<std::string>> parse_model_list(const std::string& text, const std::string& models_label);

// Refuses, before any work, an output RESULTS.h5 that cannot be written (icobrdf/io/output_path.hpp) and a
// report folder that is missing from the arguments, is not a folder, is not writable or has no writable parent.
void check_sweep_outputs(const std::string& output, const std::string& report, const std::string& report_label);

// Measures the table and every report section of `result` (its config and machine already set), draws the
// figures and writes both outputs as described above. Returns the sweep figures' file names.
std::vector<std::string> run_and_write_sweep(SweepResult& result, const std::string& output, const std::string& report,
                                             const std::string& report_label, const std::function<void(const std::string&)>& progress);

}  // namespace icobrdf::lab::sweep
