// icobrdf.Grid: the hemi-icosahedral tessellations of the upper hemisphere (icobrdf/mesh/tessellation.hpp).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include <string>

#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/core/support/memory_budget.hpp"
#include "icobrdf/mesh/tessellation.hpp"
#include "icobrdf/pipeline/resource_estimate.hpp"
#include "python/bindings.hpp"

namespace icobrdf::python {

namespace py = pybind11;

void bind_grid(py::module_& m) {
  py::class_<Grid>(m, "Grid", R"doc(A hemi-icosahedral tessellation of the upper hemisphere.

Made by ``Grid.equal_area(level)`` (every whole cell subtends exactly 4 pi / (20 4^L) sr, each half cell
half of that) or ``Grid.geodesic(level)`` (the same cells placed by the gnomonic projection).

Attributes
----------
level : int
    Subdivision level L, 0..8.
cells : int
    Number of cells, 10 4^L + 2^(L+1).
directions : ndarray, shape (cells, 3)
    Representative unit direction of each cell (+z the normal).
solid_angles : ndarray, shape (cells,)
    Solid angle of each cell in sr; they sum to 2 pi.
)doc")
      .def_static("equal_area", [](int level) {
                    if (level >= 0 && level <= kMaxTessellationLevel)  // other levels are refused by the builder
                      require_memory(grid_bytes(level), "Grid.equal_area(" + std::to_string(level) + ")", "a lower level needs 4x less per level");
                    return build_equal_area_grid(level);
                  }, py::arg("level"),
                  R"doc(The equal-area grid of a level.

Parameters
----------
level : int
    Subdivision level L, 0..8.

Returns
-------
Grid
    10 4^L + 2^(L+1) cells of equal solid angle (half cells: half of it).

Raises
------
ValueError
    For a level outside 0..8.
)doc")
      .def_static("geodesic", [](int level) { return build_geodesic_grid(level); }, py::arg("level"),
                  R"doc(The geodesic (gnomonic) grid of a level: the baseline the equal-area grid is compared with.

Parameters
----------
level : int
    Subdivision level L, 0..8.

Returns
-------
Grid
    10 4^L + 2^(L+1) cells of unequal solid angle.

Raises
------
ValueError
    For a level outside 0..8.
)doc")
      .def_property_readonly("level", [](const Grid& g) { return g.level; }, "Subdivision level L (int).")
      .def_property_readonly("cells", &Grid::cells, "Number of cells, 10 4^L + 2^(L+1) (int).")
      .def_property_readonly("directions", [](const Grid& g) { return Eigen::MatrixXd(g.directions); },
                             "Representative unit direction of each cell: ndarray of shape (cells, 3).")
      .def_property_readonly("solid_angles", [](const Grid& g) { return Eigen::VectorXd(g.solid_angles); },
                             "Solid angle of each cell in sr: ndarray of shape (cells,).")
      .def("__repr__", [](const Grid& g) {
        return "<icobrdf.Grid " + std::string(to_string(g.kind)) + " level " + std::to_string(g.level) + ", " +
               std::to_string(g.cells()) + " cells>";
      });
}

}  // namespace icobrdf::python
