// icobrdf.SampleFit: the record of a fit of scattered samples that a Spectrum carries (Spectrum.sample_fit;
// icobrdf/core/spectrum/spectrum.hpp SampleFitRecord), as `icobrdf fit` stores it in the spectrum file.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "icobrdf/core/spectrum/spectrum.hpp"
#include "python/bindings.hpp"

namespace icobrdf::python {

namespace py = pybind11;

void bind_sample_fit(py::module_& m) {
  py::class_<SampleFitRecord>(m, "SampleFit", R"doc(The figures of a least-squares fit of scattered samples (Spectrum.sample_fit).

The same figures ``icobrdf fit`` prints (``--json``: "sample_fit") and stores in the spectrum file.

Attributes
----------
samples : int
    Samples used (weight > 0; rows naming the same pair merged).
unknowns : int
    Modes fitted.
effective_rank : int
    Numerical rank of W^(1/2) A.
condition : float
    Condition number of W^(1/2) A on the kept part.
residual_rms : list of float
    Weighted RMS of values - fit at the samples, per channel [1/sr].
noise_sigma : list of float
    Estimated sigma of a weight-1 sample, per channel [1/sr] (NaN when samples <= effective_dof).
cv_rms : float
    K-fold cross-validation RMS error of the final fit [1/sr] (NaN when not measured).
cv_folds : int
    K of the cross-validation (0 when not run).
tikhonov : float
    The Tikhonov lambda used.
tikhonov_power : float
    The exponent p of the penalty d_k = (n(n+2) + m(m+2))^p.
order_choice : str
    "given" or "cross-validation".
tikhonov_choice : str
    "given" or "generalized cross-validation".
class_choice : str
    "given" or "cross-validation" (isotropic against general modes).
fallback : str
    Empty, or the fallback taken and why (e.g. general modes the samples do not determine replaced by the
    isotropic modes); ``icobrdf.fit`` also warns with it (RuntimeWarning).
solver : str
    "normal equations" or "QR".
effective_dof : float
    tr H, the effective number of parameters.
cv_rms_isotropic, cv_rms_general : float
    CV RMS of each class's own order choice when the class was chosen [1/sr]; NaN otherwise.
standard_error : ndarray, shape (channels, unknowns)
    Standard error of each mode coefficient, in the library order of the spectrum's modes (IBSSS when the
    spectrum is isotropic, BSSS otherwise); NaN where undefined.
)doc")
      .def_readonly("samples", &SampleFitRecord::samples, "Samples used (int).")
      .def_readonly("unknowns", &SampleFitRecord::unknowns, "Modes fitted (int).")
      .def_readonly("effective_rank", &SampleFitRecord::effective_rank, "Numerical rank of W^(1/2) A (int).")
      .def_readonly("condition", &SampleFitRecord::condition, "Condition number of W^(1/2) A on the kept part (float).")
      .def_readonly("residual_rms", &SampleFitRecord::residual_rms, "Weighted RMS residual per channel in 1/sr (list of float).")
      .def_readonly("noise_sigma", &SampleFitRecord::noise_sigma, "Sigma of a weight-1 sample per channel in 1/sr (list of float).")
      .def_readonly("cv_rms", &SampleFitRecord::cv_rms, "K-fold CV RMS error of the final fit in 1/sr (float).")
      .def_readonly("cv_folds", &SampleFitRecord::cv_folds, "K of the cross-validation (int).")
      .def_readonly("tikhonov", &SampleFitRecord::tikhonov, "The Tikhonov lambda used (float).")
      .def_readonly("tikhonov_power", &SampleFitRecord::tikhonov_power, "The exponent p of the penalty (float).")
      .def_readonly("order_choice", &SampleFitRecord::order_choice, "'given' or 'cross-validation' (str).")
      .def_readonly("tikhonov_choice", &SampleFitRecord::tikhonov_choice, "'given' or 'generalized cross-validation' (str).")
      .def_readonly("class_choice", &SampleFitRecord::class_choice, "'given' or 'cross-validation' (str).")
      .def_readonly("fallback", &SampleFitRecord::fallback, "Empty, or the fallback taken and why (str).")
      .def_readonly("solver", &SampleFitRecord::solver, "'normal equations' or 'QR' (str).")
      .def_readonly("effective_dof", &SampleFitRecord::effective_dof, "tr H, the effective number of parameters (float).")
      .def_readonly("cv_rms_isotropic", &SampleFitRecord::cv_rms_isotropic, "CV RMS of the isotropic modes' own choice in 1/sr (float).")
      .def_readonly("cv_rms_general", &SampleFitRecord::cv_rms_general, "CV RMS of the general modes' own choice in 1/sr (float).")
      .def_readonly("standard_error", &SampleFitRecord::standard_error,
                    "Standard error of each mode coefficient: ndarray of shape (channels, unknowns).")
      .def("__repr__", [](const SampleFitRecord& r) {
        return "<icobrdf.SampleFit " + std::to_string(r.samples) + " samples, " + std::to_string(r.unknowns) + " unknowns, order " +
               r.order_choice + ">";
      });
}

}  // namespace icobrdf::python
