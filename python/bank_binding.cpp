// icobrdf.build_bank: a LUT bank built from a scene file (icobrdf/pipeline/bank_builder.hpp), as
// `icobrdf bank build SCENE.toml -o BANK.h5` builds it in one process.
#include <pybind11/pybind11.h>

#include <iostream>
#include <string>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/progress.hpp"
#include "icobrdf/io/scene.hpp"
#include "icobrdf/pipeline/bank_builder.hpp"
#include "icobrdf/pipeline/bank_report.hpp"
#include "python/bindings.hpp"

namespace icobrdf::python {

namespace py = pybind11;
namespace {

py::object build_bank_from_scene(const std::string& scene_path, const std::string& output, bool resume, bool strict,
                                 int materials_at_once, bool progress) {
  if (materials_at_once < 0) throw ArgumentError("materials_at_once: expected 0 (chosen) or more, found " + std::to_string(materials_at_once));
  BankBuildOptions o;
  o.output = output;
  o.resume = resume;
  o.strict = strict;
  o.materials_at_once = materials_at_once;
  o.warnings = &std::cerr;
  if (progress) o.progress = [](const std::string& line) { std::cerr << (line + "\n") << std::flush; };
  BankBuildResult r;
  {
    // The long projections' own lines (icobrdf/core/support/progress.hpp) follow `progress` for this build.
    struct ProgressStream {
      std::ostream* before = progress_stream();
      explicit ProgressStream(bool on) { set_progress_stream(on ? &std::cerr : nullptr); }
      ~ProgressStream() { set_progress_stream(before); }
    } stream(progress);
    py::gil_scoped_release release;
    r = build_bank(read_scene(scene_path), o);
  }
  if (!r.written) throw UnsupportedError(bank_not_written_message(r));
  if (const std::size_t missed = targets_missed(r); missed > 0 &&
      PyErr_WarnEx(PyExc_RuntimeWarning, ("icobrdf.build_bank: " + targets_missed_message(missed)).c_str(), 1) != 0)
    throw py::error_already_set();
  return py::module_::import("json").attr("loads")(bank_build_json(r, scene_path, output).dump());
}

constexpr const char* kBuildBankDoc = R"doc(Build the LUT bank of a scene file (as ``icobrdf bank build SCENE -o OUTPUT``).

Per material the builder chooses the representation, isotropy, tessellation level and order that meet
the material's accuracy target with the fewest bytes (docs/scenes.md), and writes the bank atomically.

Parameters
----------
scene : str
    The scene file (TOML; keys in docs/scenes.md and icobrdf/io/scene.hpp).
output : str
    The bank file to write (HDF5); its resume file is OUTPUT.partial.
resume : bool, optional
    Keep the materials an interrupted build finished (default False).
strict : bool, optional
    A material with negative directional albedo fails instead of a warning on stderr (default False).
materials_at_once : int, optional
    Small materials fitted at once, each on its share of the threads (0, the default: chosen).
progress : bool, optional
    Print one line per step on stderr (default False).

Returns
-------
dict
    What ``icobrdf bank build --json`` prints: scene, output, written, interrupted, resume_file and
    materials (per material its choices and figures: representation, isotropic, level, order, target,
    error_l2, error_max, bytes, target_met, ...).

Warns
-----
RuntimeWarning
    When materials with on_miss = "keep-best" missed their target (written with target_met False).

Raises
------
RuntimeError
    For a malformed scene, or when a material failed (no bank is written; the finished materials stay
    in the resume file).
OSError
    When a file cannot be read or written.
)doc";

}  // namespace

void bind_bank(py::module_& m) {
  m.def("build_bank", &build_bank_from_scene, py::arg("scene"), py::arg("output"), py::arg("resume") = false,
        py::arg("strict") = false, py::arg("materials_at_once") = 0, py::arg("progress") = false, kBuildBankDoc);
}

}  // namespace icobrdf::python
