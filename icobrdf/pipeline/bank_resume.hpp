#pragma once
// Resuming a bank build: the finished materials are written (atomically) to OUTPUT.partial, keyed by a hash
// of the material's name (it seeds the held-out draws), the source text, the material's settings and the bank settings; with `resume`, materials whose key
// matches are taken from there. The file is rewritten after the first material, then whenever the time
// since the last rewrite reaches 10 times that rewrite's duration and at least a second (rewrites grow with
// the materials kept; this bounds them to 9% of the build, less in builds of cheap materials), and at the
// end of a failed or interrupted build: a SIGKILL loses at most that much work.
#include <chrono>
#include <cstddef>
#include <map>
#include <optional>
#include <string>

#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/scene.hpp"
#include "icobrdf/pipeline/material_report.hpp"

namespace icobrdf {

// Key of a material: everything that changes its result.
std::string material_key(const Scene& scene, const SceneMaterial& material);

// The finished materials of OUTPUT.partial by key; nullopt when the file does not exist.
std::optional<std::map<std::string, MaterialRecord>> read_resume_file(const std::string& partial_path);

// The figures and labels a bank stores with a material's choice ("choice" subgroup), and back.
void store_choice(MaterialRecord& record, const MaterialReport& report);
void report_from_record(const MaterialRecord& record, MaterialReport& report);

// Whether a rewrite is due: always when none was written yet, else once the time since the last one ended
// reaches max(10 x its duration, 1 s).
bool checkpoint_due(bool written_before, double since_last_s, double last_write_s);

// Writes OUTPUT.partial at the pace described above.
class Checkpointer {
 public:
  explicit Checkpointer(std::string partial_path) : path_(std::move(partial_path)) {}
  // `force`: write now whatever the time since the last write (if any material is new).
  void maybe_write(const BankContents& done, bool force);
  // Materials in the resume file as this build last wrote it (0: not written by this build).
  std::size_t saved() const { return saved_; }

 private:
  std::string path_;
  std::size_t saved_ = 0;  // materials in the resume file
  double last_write_s_ = 0.0;
  std::chrono::steady_clock::time_point last_end_ = std::chrono::steady_clock::now();
};

}  // namespace icobrdf
