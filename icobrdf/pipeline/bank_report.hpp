#pragma once
// What `icobrdf bank build` reports of a build (icobrdf/pipeline/bank_builder.hpp): the table or the JSON of
// its materials, and the one-line reason a bank was not written.
#include <nlohmann/json.hpp>

#include <cstddef>
#include <string>

#include "icobrdf/pipeline/bank_builder.hpp"

namespace icobrdf {

// One material's choices and figures: name, source, ok, resumed, rank (under mpirun: the rank that fitted
// it), and either error (failed) or representation, isotropic, level, order, target, error_measured, error_l2
// and error_max (null when not measured: delta BRDFs), anisotropy, kept_coefficients, total_coefficients,
// bytes, seconds, metric, asymmetry (the data's own non-reciprocal fraction; null when not measured), noise (the
// data's noise figure from its own grid, icobrdf/pipeline/held_out.hpp; null when the source has none),
// judged_against ("reciprocal part" or "data"), grazing_share, target_met and max_bytes (null when none).
nlohmann::json material_report_json(const MaterialReport& m);

// The table of the build's materials, one line each: name, representation, isotropic, level, order, target,
// met, relative L2 and max errors ("n/a" when not measured), the data's asymmetry and noise, kept/total coefficients, bytes,
// seconds, then a note per material whose target lies below its data's asymmetry or whose metric "f" is dominated
// by grazing pairs; a failed
// material's line gives its error (and its rank under mpirun); "wrote OUTPUT" last when the bank was written.
std::string bank_build_table(const BankBuildResult& r, const std::string& output);

// Share of the reference's norm from pairs beyond 80 degrees above which the table notes that metric "f" is
// dominated by grazing values a renderer scales by cos theta < 0.17: half.
inline constexpr double kGrazingDominates = 0.5;
// Materials written although they missed their target (on_miss = "keep-best").
std::size_t targets_missed(const BankBuildResult& r);
// "N material(s) missed their target and were written with the lowest error within their max_bytes (...)".
std::string targets_missed_message(std::size_t missed);

// The JSON of the whole build: scene, output, written, interrupted, resume_file, materials.
nlohmann::json bank_build_json(const BankBuildResult& r, const std::string& scene, const std::string& output);

// Why the bank of `r` was not written: "bank not written: N material(s) failed (see above); " followed by
// kept_for_resume(r); under mpirun it first names the first failed material and its rank.
std::string bank_not_written_message(const BankBuildResult& r);

}  // namespace icobrdf
