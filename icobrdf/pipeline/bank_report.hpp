#pragma once
// What `icobrdf bank build` reports of a build (icobrdf/pipeline/bank_builder.hpp): the table or the JSON of
// its materials, and the one-line reason a bank was not written.
#include <nlohmann/json.hpp>

#include <string>

#include "icobrdf/pipeline/bank_builder.hpp"

namespace icobrdf {

// One material's choices and figures: name, source, ok, resumed, rank (under mpirun: the rank that fitted
// it), and either error (failed) or representation, isotropic, level, order, target, error_measured, error_l2
// and error_max (null when not measured: delta BRDFs), anisotropy, kept_coefficients, total_coefficients,
// bytes, seconds.
nlohmann::json material_report_json(const MaterialReport& m);

// The table of the build's materials, one line each: name, representation, isotropic, level, order, target,
// relative L2 and max errors ("n/a" when not measured), kept/total coefficients, bytes, seconds; a failed
// material's line gives its error (and its rank under mpirun); "wrote OUTPUT" last when the bank was written.
std::string bank_build_table(const BankBuildResult& r, const std::string& output);

// The JSON of the whole build: scene, output, written, interrupted, resume_file, materials.
nlohmann::json bank_build_json(const BankBuildResult& r, const std::string& scene, const std::string& output);

// Why the bank of `r` was not written: "bank not written: N material(s) failed (see above); " followed by
// kept_for_resume(r); under mpirun it first names the first failed material and its rank.
std::string bank_not_written_message(const BankBuildResult& r);

}  // namespace icobrdf
