// The discrete engine from Python: icobrdf.lut (icobrdf/core/projection/lut.hpp), DiscreteBasis
// (icobrdf/core/projection/discrete_basis.hpp), Projection, project, reconstruct, smooth
// (icobrdf/core/projection/projection.hpp) and evaluate_coefficients (icobrdf/core/spectrum/spectrum_ops.hpp).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "icobrdf/core/basis/lowpass_filter.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/projection/discrete_basis.hpp"
#include "icobrdf/core/projection/lut.hpp"
#include "icobrdf/core/projection/projection.hpp"
#include "icobrdf/core/spectrum/spectrum_ops.hpp"
#include "icobrdf/core/support/memory_budget.hpp"
#include "icobrdf/pipeline/resource_estimate.hpp"
#include "python/array_arguments.hpp"
#include "python/bindings.hpp"

namespace icobrdf::python {
namespace {

std::vector<Eigen::MatrixXd> lut_of(const std::string& model_spec, const Grid& grid, bool cosine, const std::string& sampling) {
  const auto model = parse_model_source(model_spec);
  const auto s = lut_sampling_named(sampling);
  if (!s) throw ArgumentError("sampling: expected 'average' or 'centre', found '" + quoted_text(sampling) + "'");
  require_memory(lut_table_bytes(grid.cells(), model->channels()), "lut(" + model_spec + ") on a grid of " + std::to_string(grid.cells()) + " cells",
                 "a grid of a lower level needs 16x less per level");
  py::gil_scoped_release release;
  return build_lut(*model, grid, cosine || !model->delta_parts().empty(), *s).channels;
}

Eigen::VectorXd coefficients_at(const Eigen::MatrixXd& c, int order, const DirArray& wi, const DirArray& wr) {
  require_finite_argument(c, "coefficients");
  const Eigen::MatrixXd f = eval_chunked(wi, wr, 1, [&](const RowMatrix3d& a, const RowMatrix3d& b) {
    return Eigen::MatrixXd(evaluate_coefficients(c, order, a, b));
  });
  return Eigen::VectorXd(f.col(0));
}

constexpr const char* kLutDoc = R"doc(The cells x cells LUT of a model on a grid, per channel.

Parameters
----------
model : str
    The model's SOURCE text, ``model:NAME[:key=value,...]``.
grid : Grid
    The grid whose cells index the LUT's rows (incident) and columns (remitted).
cosine : bool, optional
    Tabulate g = f cos(theta_i) instead of f (always for a model with delta parts; default False).
sampling : {'average', 'centre'}, optional
    Each entry is the cell's cubature average of f over both cells (default) or f at the cells' centres.

Returns
-------
list of ndarray, shape (cells, cells)
    One LUT per channel, in 1/sr.

Raises
------
ValueError
    For an unknown model, a bad parameter or an unknown sampling.
)doc";

constexpr const char* kDiscreteBasisDoc = R"doc(The hemisphere basis sampled on a grid.

Parameters
----------
grid : Grid
    The tessellation.
order : int
    Total order N, 0..128; M = (N + 1)(N + 2) / 2 modes.

Attributes
----------
order : int
    Total order N.
B : ndarray, shape (cells, M)
    B_cj = the average of K_j over cell c, by the cell's cubature.
W : ndarray, shape (cells,)
    Solid angles of the cells in sr.
G : ndarray, shape (M, M)
    Gram matrix B^T W B; the identity for the continuous basis.
gram_error : float
    max |G - I|: how well the grid resolves order N.
condition : float
    lambda_max(G) / lambda_min(G).

Raises
------
ValueError
    For an order outside 0..128.
)doc";

constexpr const char* kProjectionDoc = R"doc(The least-squares projection operator of a discrete basis.

Parameters
----------
basis : DiscreteBasis
    The basis sampled on the grid.

Attributes
----------
P : ndarray, shape (cells, M)
    P = W B G^-1, so that C = P^T F P for a LUT F.

Raises
------
RuntimeError
    When G is not positive definite (the message gives its condition number).
)doc";

constexpr const char* kSmoothDoc = R"doc(Smooth a LUT: S F S^T with S = B P^T, filtered.

Parameters
----------
basis : DiscreteBasis
    The basis sampled on the LUT's grid.
projection : Projection
    Its projection operator.
lut : ndarray, shape (cells, cells)
    The LUT F in 1/sr.
filter : str, optional
    Low-pass filter applied to the coefficients: none (plain truncation, the default), fejer, lanczos,
    hann, gaussian[:width=W].

Returns
-------
ndarray, shape (cells, cells)
    The smoothed LUT in 1/sr.

Raises
------
ValueError
    For an unknown filter or shapes that do not match.
)doc";

constexpr const char* kEvaluateDoc = R"doc(f = sum_ab C_ab K_a(wi) K_b(wr) of a coefficient matrix at direction pairs.

Parameters
----------
coefficients : ndarray, shape (M, M)
    C, M = (N + 1)(N + 2) / 2 in ANSI order.
order : int
    Total order N of C.
wi, wr : array_like, shape (n, 3) or (3,)
    Incident and remitted unit directions, pair by pair; +z the normal.

Returns
-------
ndarray, shape (n,)
    f(wi[r], wr[r]) in 1/sr.

Raises
------
ValueError
    For shapes that do not match, or a direction that is not finite or lies below the horizon.
)doc";

}  // namespace

void bind_operators(py::module_& m) {
  m.def("lut", &lut_of, py::arg("model"), py::arg("grid"), py::arg("cosine") = false, py::arg("sampling") = "average", kLutDoc);
  py::class_<DiscreteBasis>(m, "DiscreteBasis", kDiscreteBasisDoc)
      .def(py::init([](const Grid& g, int order) {
             if (order >= 0)  // build_discrete_basis refuses a negative order itself
               require_memory(basis_bytes(g.cells(), order), "DiscreteBasis of order " + std::to_string(order) + " on " + std::to_string(g.cells()) + " cells",
                              "a lower order or level needs less");
             py::gil_scoped_release release;
             return build_discrete_basis(g, order);
           }),
           py::arg("grid"), py::arg("order"))
      .def_readonly("order", &DiscreteBasis::order, "Total order N (int).")
      .def_readonly("B", &DiscreteBasis::B, "Cell averages of the basis: ndarray of shape (cells, M).")
      .def_readonly("W", &DiscreteBasis::W, "Solid angles of the cells in sr: ndarray of shape (cells,).")
      .def_readonly("G", &DiscreteBasis::G, "Gram matrix B^T W B: ndarray of shape (M, M).")
      .def_readonly("gram_error", &DiscreteBasis::gram_error, "max |G - I| (float).")
      .def_readonly("condition", &DiscreteBasis::condition, "lambda_max(G) / lambda_min(G) (float).")
      .def(
          "check_supported", [](const DiscreteBasis& b, double tol) { check_supported(b, tol); }, py::arg("tolerance") = kDefaultGramTolerance,
          R"doc(Check that the grid resolves the basis's order.

Parameters
----------
tolerance : float, optional
    Largest Gram error max |G - I| accepted (default 0.1).

Returns
-------
None

Raises
------
RuntimeError
    When the Gram error exceeds the tolerance; the message names the largest order the grid supports.
)doc");
  py::class_<ProjectionOperator>(m, "Projection", kProjectionDoc)
      .def(py::init([](const DiscreteBasis& b) { return make_projection(b); }), py::arg("basis"))
      .def_readonly("P", &ProjectionOperator::P, "P = W B G^-1: ndarray of shape (cells, M).");
  m.def(
      "project",
      [](const ProjectionOperator& p, const Eigen::MatrixXd& lut) {
        require_finite_argument(lut, "lut");
        py::gil_scoped_release release;
        return project_lut(p, lut);
      },
      py::arg("projection"), py::arg("lut"), R"doc(Project a LUT onto the basis: C = P^T F P.

Parameters
----------
projection : Projection
    The projection operator of the LUT's grid.
lut : ndarray, shape (cells, cells)
    The LUT F in 1/sr.

Returns
-------
ndarray, shape (M, M)
    The coefficient matrix C.

Raises
------
ValueError
    When the LUT's shape does not match the grid.
)doc");
  m.def(
      "reconstruct",
      [](const DiscreteBasis& b, const Eigen::MatrixXd& c) {
        require_finite_argument(c, "coefficients");
        py::gil_scoped_release release;
        return reconstruct_lut(b, c);
      },
      py::arg("basis"), py::arg("coefficients"), R"doc(The LUT of a coefficient matrix: F = B C B^T.

Parameters
----------
basis : DiscreteBasis
    The basis sampled on the grid.
coefficients : ndarray, shape (M, M)
    The coefficient matrix C.

Returns
-------
ndarray, shape (cells, cells)
    F in 1/sr: the cell averages of the expansion.

Raises
------
ValueError
    When C's shape does not match the basis.
)doc");
  m.def(
      "smooth",
      [](const DiscreteBasis& b, const ProjectionOperator& p, const Eigen::MatrixXd& lut, const std::string& filter) {
        require_finite_argument(lut, "lut");
        const LowPassFilter f = parse_lowpass_filter(filter);
        py::gil_scoped_release release;
        return smooth_lut(b, p, lut, f);
      },
      py::arg("basis"), py::arg("projection"), py::arg("lut"), py::arg("filter") = "none", kSmoothDoc);
  m.def("evaluate_coefficients", &coefficients_at, py::arg("coefficients"), py::arg("order"), py::arg("wi"), py::arg("wr"), kEvaluateDoc);
}

}  // namespace icobrdf::python
