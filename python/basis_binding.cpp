// The hemisphere basis and the modes at directions: icobrdf.basis_count, hemisphere_basis, helmholtz_modes,
// isotropic_modes (icobrdf/core/basis/hemisphere_basis.hpp, helmholtz_modes.hpp, isotropic_modes.hpp).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include "icobrdf/core/basis/helmholtz_modes.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "python/array_arguments.hpp"
#include "python/bindings.hpp"

namespace icobrdf::python {

void bind_basis(py::module_& m) {
  m.def("basis_count", &hemisphere_basis_count, py::arg("order"), R"doc(Number of hemisphere functions K_n^l up to a total order.

Parameters
----------
order : int
    Total order N, 0..128.

Returns
-------
int
    M = (N + 1)(N + 2) / 2.

Raises
------
ValueError
    For an order outside 0..128.
)doc");
  m.def(
      "hemisphere_basis",
      [](int order, const DirArray& dirs) {
        const RowMatrix3d d = directions(dirs, "dirs");
        py::gil_scoped_release release;
        return hemisphere_basis_matrix(order, d);
      },
      py::arg("order"), py::arg("dirs"), R"doc(Values of every hemisphere function K_j, j < M, at directions.

The K_n^l are orthonormal with the solid-angle measure on the upper hemisphere, in ANSI order
j = (n (n + 2) + l) / 2.

Parameters
----------
order : int
    Total order N, 0..128.
dirs : array_like, shape (n, 3) or (3,)
    Unit directions, +z the normal, z >= 0.

Returns
-------
ndarray, shape (n, M)
    K_j(dirs[r]) in 1/sqrt(sr), M = (N + 1)(N + 2) / 2. Absolute error <= 1e-13 sqrt((n + 1) / pi) for
    order <= 128.

Raises
------
ValueError
    For an order outside 0..128, or dirs not unit vectors of shape (n, 3) (or (3,): one direction).
)doc");
  m.def(
      "helmholtz_modes",
      [](int order, const DirArray& wi, const DirArray& wr) {
        const auto [a, b] = direction_pairs(wi, wr);
        py::gil_scoped_release release;
        return helmholtz_modes_eval(order, a, b);
      },
      py::arg("order"), py::arg("wi"), py::arg("wr"), R"doc(Values of every Helmholtz (BSSS) mode at direction pairs.

H_ab(wi, wr) = (K_a(wi) K_b(wr) + K_b(wi) K_a(wr)) / sqrt(2) for a < b, K_a(wi) K_a(wr) for a = b:
orthonormal on hemisphere x hemisphere and spanning the reciprocal functions. Library order: b ascending,
then a ascending.

Parameters
----------
order : int
    Total order N, 0..128.
wi, wr : array_like, shape (n, 3) or (3,)
    Incident and remitted unit directions, pair by pair.

Returns
-------
ndarray, shape (n, M (M + 1) / 2)
    H_ab(wi[r], wr[r]) in 1/sr, M = (N + 1)(N + 2) / 2.

Raises
------
ValueError
    For an order outside 0..128, or wi, wr not unit vectors of shape (n, 3) with the same n (or (3,): one direction paired with every row of the other).
)doc");
  m.def(
      "isotropic_modes",
      [](int order, const DirArray& wi, const DirArray& wr) {
        const auto [a, b] = direction_pairs(wi, wr);
        py::gil_scoped_release release;
        return isotropic_modes_eval(order, a, b);
      },
      py::arg("order"), py::arg("wi"), py::arg("wr"), R"doc(Values of every isotropic (IBSSS) mode I_nm^l at direction pairs.

The isotropic modes span the reciprocal functions of theta_i, theta_r and cos(phi_i - phi_r); they are
orthonormal on hemisphere x hemisphere. Order of the paper's Table 2: n, then m, then l ascending.

Parameters
----------
order : int
    Total order N, 0..128.
wi, wr : array_like, shape (n, 3) or (3,)
    Incident and remitted unit directions, pair by pair.

Returns
-------
ndarray, shape (n, count)
    I_nm^l(wi[r], wr[r]) in 1/sr; count is 1, 2, 5, 8, 14, ... for N = 0, 1, 2, 3, 4, ...

Raises
------
ValueError
    For an order outside 0..128, or wi, wr not unit vectors of shape (n, 3) with the same n (or (3,): one direction paired with every row of the other).
)doc");
}

}  // namespace icobrdf::python
