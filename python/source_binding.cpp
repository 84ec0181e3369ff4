// icobrdf.Source (a SOURCE opened once, icobrdf/io/brdf_source.hpp) and icobrdf.models (the analytic models,
// icobrdf/core/models/model_registry.hpp).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <vector>

#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/sample_arrays.hpp"
#include "python/bindings.hpp"
#include "python/py_source.hpp"

namespace icobrdf::python {
namespace {

// Source.from_samples: the samples as a CSV file's (icobrdf/io/sample_arrays.hpp), with the fit options of its
// SOURCE text (tikhonov=L|auto, power=P, rank-tol=T).
PySource from_samples(const DirArray& wi, const DirArray& wr, const Eigen::MatrixXd& values, const std::optional<Eigen::VectorXd>& weights,
                      const py::object& tikhonov, double power, const std::optional<double>& rank_tol, const std::string& name) {
  SampleArrayFit o;
  if (py::isinstance<py::str>(tikhonov)) {
    const auto text = tikhonov.cast<std::string>();
    if (text != "auto") throw ArgumentError("tikhonov: expected None, 'auto' or a lambda >= 0, found '" + quoted_text(text) + "'");
    o.tikhonov_auto = true;
  } else if (!tikhonov.is_none()) {
    o.fit.tikhonov = tikhonov.cast<double>();
  }
  o.fit.tikhonov_power = power;
  if (rank_tol) o.fit.rank_tolerance = *rank_tol;
  const auto [a, b] = direction_pairs(wi, wr);
  return PySource{std::shared_ptr<BrdfSource>(open_sample_arrays(samples_from_arrays(a, b, values, weights.value_or(Eigen::VectorXd())), o, name))};
}

constexpr const char* kFromSamplesDoc = R"doc(A Source of scattered samples given as arrays, fitted as a CSV file of them.

``icobrdf.fit`` fits it exactly as ``icobrdf fit FILE.csv[#tikhonov=...,power=...,rank-tol=...]`` fits the
same samples: weighted least squares on the Helmholtz modes; with ``order=None`` the order and the class of
modes (isotropic or general) by 5-fold cross-validation and lambda by GCV; the same fallbacks and checks.
Rows naming the same pair are merged as a CSV file's duplicate rows are (weighted mean, summed weight).

Parameters
----------
wi, wr : array_like, shape (n, 3) or (3,)
    Incident (toward the light) and remitted unit directions, pair by pair, +z the normal, z >= 0; a single
    direction of shape (3,) is paired with every row of the other.
values : array_like, shape (n, channels) or (n,)
    f in 1/sr at each pair, finite (negative values are accepted as noise).
weights : array_like, shape (n,), optional
    Finite weights >= 0 of the samples (0: left out); default 1 each.
tikhonov : None, 'auto' or float, optional
    The Tikhonov penalty lambda * sum_k d_k x_k^2, d_k = (n(n+2) + m(m+2))^p: None (the default: lambda by
    GCV when the order is chosen, else 0), 'auto' (lambda by generalized cross-validation) or lambda >= 0.
power : float, optional
    The exponent p of the penalty (default 1; 0 = plain ridge).
rank_tol : float, optional
    Relative singular-value threshold of the rank (default max(samples, unknowns) * 2.2e-16).
name : str, optional
    The source's name (its ``spec`` and the fitted spectrum's ``source``; default "arrays").

Returns
-------
Source
    A source that can be fitted (``icobrdf.fit``) but not evaluated: samples have no value between them.

Raises
------
ValueError
    For arrays of the wrong shape, directions that are not unit vectors above the horizon, values that
    are not finite, negative weights, or a bad tikhonov, power or rank_tol.
)doc";

}  // namespace

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
wi, wr : array_like, shape (n, 3) or (3,)
    Incident (toward the light) and remitted unit directions, pair by pair; +z the normal. A single
    direction of shape (3,) is paired with every row of the other.

Returns
-------
ndarray, shape (n, channels)
    f(wi[r], wr[r]) in 1/sr.

Raises
------
ValueError
    For wi, wr not of shape (n, 3) with the same n (or (3,)), or rows that are not unit vectors (length 1
    within 1e-10).
)doc")
      .def_static("from_samples", &from_samples, py::arg("wi"), py::arg("wr"), py::arg("values"), py::arg("weights") = py::none(),
                  py::arg("tikhonov") = py::none(), py::arg("power") = 1.0, py::arg("rank_tol") = py::none(), py::arg("name") = "arrays",
                  kFromSamplesDoc)
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
