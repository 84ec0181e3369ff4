// icobrdf.Spectrum (icobrdf/core/spectrum/spectrum.hpp) and the functions that make, read and write it:
// fit (icobrdf/pipeline/fit_source.hpp), read_spectrum, write_spectrum, bank_materials (icobrdf/io/bank_file.hpp).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <vector>

#include "icobrdf/core/basis/lowpass_filter.hpp"
#include "icobrdf/core/projection/discrete_basis.hpp"
#include "icobrdf/core/projection/lut.hpp"
#include "icobrdf/core/spectrum/spectrum.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/spectrum_file.hpp"
#include "icobrdf/pipeline/fit_order.hpp"
#include "icobrdf/pipeline/fit_source.hpp"
#include "python/bindings.hpp"
#include "python/py_source.hpp"

namespace icobrdf::python {
namespace {

Spectrum fit(const PySource& src, int level, std::optional<int> order, bool isotropic, bool cosine, const std::string& filter,
             const std::string& sampling, double gram_tolerance) {
  FitRequest r;
  r.level = level;
  if (order && *order < 0) throw ArgumentError("order: expected an order >= 0 or None, found " + std::to_string(*order));
  r.order = fit_order_for(*src.source, order);
  r.isotropic = isotropic;
  r.cosine = cosine;
  r.filter = parse_lowpass_filter(filter);
  r.gram_tolerance = gram_tolerance;
  const auto s = lut_sampling_named(sampling);
  if (!s) throw ArgumentError("sampling: expected 'average' or 'centre', found '" + quoted_text(sampling) + "'");
  r.sampling = *s;
  Spectrum out;
  {
    py::gil_scoped_release release;
    out = fit_source(*src.source, r).spectrum;
  }
  // A fit that did not fit what was asked says so, as `icobrdf fit` does on stderr.
  if (out.sample_fit && !out.sample_fit->fallback.empty() &&
      PyErr_WarnEx(PyExc_RuntimeWarning, ("icobrdf.fit " + out.source + ": " + out.sample_fit->fallback).c_str(), 1) != 0)
    throw py::error_already_set();
  return out;
}

constexpr const char* kSpectrumDoc = R"doc(Coefficients of a BRDF in the hemisphere basis.

f(wi, wr) = sum_ab C_ab K_a(wi) K_b(wr), with one symmetric M x M matrix C per channel, M = (N + 1)(N + 2) / 2
in ANSI order.

Attributes
----------
order : int
    Total order N.
isotropic : bool
    Whether C lies in the isotropic subspace.
cosine : bool
    Whether C holds the coefficients of g = f cos(theta_i) instead of f.
source : str
    The canonical SOURCE text it came from.
level : int
    Tessellation level it was fitted on (-1: no tessellation took part).
filter : str
    The low-pass filter applied ("none" when none).
gram_error : float
    max |G - I| of the fitting grid at this order.
max_albedo : float
    Largest directional albedo over the fitting grid's directions.
coefficients : list of ndarray, shape (M, M)
    C per channel.
channel_names : list of str
    Labels of the channels (RGB or wavelengths); empty when unlabelled.
sample_fit : SampleFit or None
    For a fit of scattered samples: CV error, standard errors, residual RMS, condition and the choices made.
)doc";

constexpr const char* kFitDoc = R"doc(Project a source onto the modes on the equal-area grid (as ``icobrdf fit``).

Parameters
----------
source : Source
    The BRDF to fit.
level : int, optional
    Equal-area tessellation level, 0..8 (default 4); scattered samples use it only for the max_albedo figure.
order : int or None, optional
    Total order N of the expansion, 0..128; the grid must resolve it. None (the default): scattered samples
    (CSV files, ``Source.from_samples``) choose the order and the class of modes (isotropic or general) by
    5-fold cross-validation, and the Tikhonov lambda by GCV unless given, as ``icobrdf fit`` without
    ``--order``; other sources take order 8.
isotropic : bool, optional
    Project onto the isotropic modes (default False).
cosine : bool, optional
    Fit g = f cos(theta_i) instead of f (always for delta models; default False).
filter : str, optional
    Low-pass filter: none, fejer, lanczos, hann, gaussian[:width=W] (default none).
sampling : {'average', 'centre'}, optional
    How the grid samples each cell: the cell's cubature average (default) or its centre.
gram_tolerance : float, optional
    Largest Gram error max |G - I| accepted for (grid, order) (default 0.1).

Returns
-------
Spectrum
    The fitted coefficients, with the fit's figures; for scattered samples ``Spectrum.sample_fit`` holds the
    CV error, standard errors, residual RMS, condition and the choices made.

Warns
-----
RuntimeWarning
    When a fit of samples did not fit what was asked: general modes the samples do not determine (in-plane
    data, unseen modes, condition > 1e6) replaced by the isotropic modes, or those by a regularized fit. The
    same text is in ``Spectrum.sample_fit.fallback``.

Raises
------
ValueError
    For a bad argument (level, order, filter, sampling).
RuntimeError
    When the grid does not resolve the order within gram_tolerance, or for malformed source data.
MemoryError
    When the fit needs more memory than the machine offers.
)doc";

constexpr const char* kReadSpectrumDoc = R"doc(Read the spectrum of one material of a spectrum file or a bank.

Parameters
----------
path : str
    The HDF5 file (docs/file-format.md).
material : str, optional
    The material's name; empty (the default): the first in name order.

Returns
-------
Spectrum
    The material's stored coefficients.

Raises
------
OSError
    When the file cannot be read.
RuntimeError
    For a malformed file or a missing material.
)doc";

constexpr const char* kWriteSpectrumDoc = R"doc(Write a spectrum file holding one material, atomically.

Parameters
----------
path : str
    The HDF5 file to write (replaced whole, or left as it was on failure).
spectrum : Spectrum
    The coefficients to store.
material : str, optional
    The material's name in the file (default "material"): 1 to 255 bytes of printable ASCII without '/' or '.'.

Returns
-------
None

Raises
------
ValueError
    For an invalid material name.
OSError
    When the file cannot be written.
)doc";

constexpr const char* kBankMaterialsDoc = R"doc(Names of the materials of a bank or spectrum file.

Parameters
----------
path : str
    The HDF5 file.

Returns
-------
list of str
    The material names, in name order.

Raises
------
OSError
    When the file cannot be read.
RuntimeError
    For a malformed file.
)doc";

}  // namespace

void bind_spectrum(py::module_& m) {
  py::class_<Spectrum>(m, "Spectrum", kSpectrumDoc)
      .def_readonly("order", &Spectrum::order, "Total order N (int).")
      .def_readonly("isotropic", &Spectrum::isotropic, "Whether C lies in the isotropic subspace (bool).")
      .def_readonly("cosine", &Spectrum::cosine, "Whether C holds the coefficients of g = f cos(theta_i) instead of f (bool).")
      .def_readonly("source", &Spectrum::source, "The canonical SOURCE text it came from (str).")
      .def_readonly("level", &Spectrum::level, "Tessellation level it was fitted on, -1 when none took part (int).")
      .def_readonly("filter", &Spectrum::filter, "The low-pass filter applied (str).")
      .def_readonly("gram_error", &Spectrum::gram_error, "max |G - I| of the fitting grid at this order (float).")
      .def_readonly("max_albedo", &Spectrum::max_albedo, "Largest directional albedo over the fitting grid's directions (float).")
      .def_property_readonly("coefficients", [](const Spectrum& s) { return s.channels; },
                             "C per channel: list of ndarray of shape (M, M).")
      .def_readonly("channel_names", &Spectrum::channel_names, "Labels of the channels (RGB or wavelengths); empty when unlabelled.")
      .def_readonly("sample_fit", &Spectrum::sample_fit,
                    "The figures of a fit of scattered samples (SampleFit), None for other spectra.")
      .def(
          "eval",
          [](const Spectrum& s, const DirArray& wi, const DirArray& wr) {
            const auto src = spectrum_source(s);
            return eval_source(*src, wi, wr);
          },
          py::arg("wi"), py::arg("wr"), R"doc(The expansion's f at direction pairs.

Parameters
----------
wi, wr : array_like, shape (n, 3) or (3,)
    Incident and remitted unit directions, pair by pair; +z the normal.

Returns
-------
ndarray, shape (n, channels)
    f(wi[r], wr[r]) in 1/sr (a spectrum of g is divided by cos(theta_i)).

Raises
------
ValueError
    For wi, wr not unit vectors of shape (n, 3) with the same n (or (3,): one direction paired with every row
    of the other), or directions below the horizon.
)doc")
      .def("__repr__", [](const Spectrum& s) {
        return "<icobrdf.Spectrum order " + std::to_string(s.order) + ", " + std::to_string(s.channel_count()) + " channel(s) of " +
               s.source + ">";
      });
  m.def("fit", &fit, py::arg("source"), py::arg("level") = 4, py::arg("order") = py::none(), py::arg("isotropic") = false,
        py::arg("cosine") = false, py::arg("filter") = "none", py::arg("sampling") = "average",
        py::arg("gram_tolerance") = kDefaultGramTolerance, kFitDoc);
  m.def(
      "read_spectrum",
      [](const std::string& path, const std::string& name) {
        return read_spectrum_file(path, name, "icobrdf.Spectrum holds Zernike modes only; evaluate it with icobrdf.Source('FILE.h5#MATERIAL')");
      },
        py::arg("path"), py::arg("material") = "", kReadSpectrumDoc);
  m.def(
      "write_spectrum",
      [](const std::string& path, const Spectrum& s, const std::string& name) { write_spectrum_file(path, s, nullptr, name); },
      py::arg("path"), py::arg("spectrum"), py::arg("material") = "material", kWriteSpectrumDoc);
  m.def(
      "bank_materials",
      [](const std::string& path) {
        std::vector<std::string> names;
        for (const auto& mat : read_bank(path, ReadOptions{.read_luts = false}).materials) names.push_back(mat.name);
        return names;
      },
      py::arg("path"), kBankMaterialsDoc);
}

}  // namespace icobrdf::python
