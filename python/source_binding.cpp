// icobrdf.Source (a SOURCE opened once, icobrdf/io/brdf_source.hpp) and icobrdf.models (the analytic models,
// icobrdf/core/models/model_registry.hpp).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "icobrdf/core/models/model_registry.hpp"
#include "python/bindings.hpp"
#include "python/py_source.hpp"

namespace icobrdf::python {

void bind_source(py::module_& m) {
  py::class_<PySource>(m, "Source", R"doc(A BRDF source, opened once.

Parameters
----------
text : str
    The SOURCE: ``model:NAME[:key=value,...]`` (angles in degrees; ``icobrdf.models()`` lists the names),
    ``FILE.h5[#MATERIAL]`` (a spectrum file or a bank), a MERL table, an RGL ``.bsdf`` file, CSV samples or a
    SCATMECH coefficient file.

Attributes
----------
spec : str
    The canonical SOURCE text.
channels : int
    Number of channels of f (1, 3, or the wavelengths of a spectral material).
has_delta : bool
    Whether the BRDF has delta parts (mirror, retroreflector), which have no pointwise value.

Raises
------
ValueError
    For an unknown model or a bad parameter.
OSError
    For a file that cannot be read.
RuntimeError
    For a malformed file.
)doc")
      .def(py::init([](const std::string& text) { return PySource{std::shared_ptr<BrdfSource>(open_source(text))}; }),
           py::arg("text"))
      .def_property_readonly("spec", [](const PySource& s) { return s.source->spec(); }, "The canonical SOURCE text (str).")
      .def_property_readonly("channels", [](const PySource& s) { return s.source->channels(); }, "Number of channels of f (int).")
      .def_property_readonly("has_delta", [](const PySource& s) { return s.source->has_delta(); },
                             "Whether the BRDF has delta parts, which have no pointwise value (bool).")
      .def(
          "eval", [](const PySource& s, const DirArray& wi, const DirArray& wr) { return eval_source(*s.source, wi, wr); },
          py::arg("wi"), py::arg("wr"), R"doc(The BRDF f at direction pairs.

Delta parts have no pointwise value: only the regular part is evaluated.

Parameters
----------
wi, wr : array_like, shape (n, 3)
    Incident (toward the light) and remitted unit directions, pair by pair; +z the normal.

Returns
-------
ndarray, shape (n, channels)
    f(wi[r], wr[r]) in 1/sr.

Raises
------
ValueError
    For wi, wr not of shape (n, 3) with the same n.
)doc")
      .def("__repr__", [](const PySource& s) { return "<icobrdf.Source " + s.source->spec() + ">"; });
  m.def(
      "models",
      [] {
        std::vector<std::string> names;
        for (const auto& info : model_registry()) names.push_back(info.name);
        return names;
      },
      R"doc(Names of the analytic BRDF models.

Returns
-------
list of str
    The NAME of each model, usable as the SOURCE ``model:NAME``.
)doc");
}

}  // namespace icobrdf::python
