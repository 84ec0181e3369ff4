// icobrdf.Sampler: importance sampling of reflected directions from a Source (icobrdf/io/material_sampler.hpp).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include <string>

#include "icobrdf/core/projection/lut.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/mesh/tessellation.hpp"
#include "icobrdf/pipeline/resource_estimate.hpp"
#include "python/bindings.hpp"
#include "python/py_source.hpp"

namespace icobrdf::python {
namespace {

PySampler make_sampler(const PySource& src, int level, const std::string& cell_value) {
  const auto s = lut_sampling_named(cell_value);
  if (!s) throw ArgumentError("cell_value: expected 'centre' or 'average', found '" + quoted_text(cell_value) + "'");
  if (level >= 0 && level <= kMaxTessellationLevel)  // the sampler refuses other levels itself
    require_sampling_memory(level, *s == LutSampling::CellAverage, src.source->channels(), "Sampler(" + src.source->spec() + ")");
  py::gil_scoped_release release;
  return PySampler{MaterialSampler(src.source, level, *s)};
}

py::tuple sample(const PySampler& s, const Eigen::Ref<const Eigen::VectorXd>& wi, const Eigen::VectorXd& u1, const Eigen::VectorXd& u2) {
  const Eigen::Vector3d w = incident_direction(wi);
  MaterialSamples out;
  {
    py::gil_scoped_release release;
    out = s.sampler.sample(w, u1, u2);
  }
  return py::make_tuple(Eigen::MatrixXd(out.directions), out.pdf, out.weight);
}

Eigen::VectorXd pdf(const PySampler& s, const Eigen::Ref<const Eigen::VectorXd>& wi, const DirArray& wr) {
  const Eigen::Vector3d w = incident_direction(wi);
  const RowMatrix3d r = directions(wr, "wr");
  py::gil_scoped_release release;
  return s.sampler.pdf(w, r);
}

}  // namespace

void bind_sampler(py::module_& m) {
  py::class_<PySampler>(m, "Sampler", R"doc(Importance sampling of reflected directions from a Source.

For an incident direction wi, cell k of the equal-area grid of `level` is drawn with probability
proportional to max(f(wi, .), 0) cos(theta) integrated over the cell, then a direction uniform in solid
angle inside the cell: the density is piecewise constant over the cells.

Parameters
----------
source : Source
    The BRDF to sample (kept alive by the sampler).
level : int, optional
    Equal-area grid level of the density, 0..8 (default 5: 10,304 cells of 1.4 degrees).
cell_value : {'centre', 'average'}, optional
    Cell masses from f at each cell's direction ('centre', the default) or from a degree-2 cubature over
    each cell ('average').

Attributes
----------
level : int
    The grid level of the density.

Raises
------
ValueError
    For a level outside 0..8 or an unknown cell_value.
)doc")
      .def(py::init(&make_sampler), py::arg("source"), py::arg("level") = kDefaultSamplingLevel, py::arg("cell_value") = "centre")
      .def_property_readonly("level", [](const PySampler& s) { return s.sampler.level(); }, "The grid level of the density (int).")
      .def("sample", &sample, py::arg("wi"), py::arg("u1"), py::arg("u2"), R"doc(Draws reflected directions for one incident direction.

Parameters
----------
wi : array_like, shape (3,)
    Incident unit direction (toward the light), +z the normal.
u1, u2 : array_like, shape (n,)
    Uniform numbers in [0, 1): u1 chooses the cell, u2 the direction inside it.

Returns
-------
wr : ndarray, shape (n, 3)
    The drawn unit directions.
pdf : ndarray, shape (n,)
    Their density in 1/sr.
weight : ndarray, shape (n, channels)
    f(wi, wr) cos(theta_r) / pdf: the Monte Carlo weight of each draw.

Raises
------
ValueError
    For wi not a unit vector of 3 values above the horizon, or u1, u2 of different lengths or outside [0, 1].
RuntimeError
    When f(wi, .) is not finite at a cell, or its mass is zero at every cell (an all-zero row, a delta-only
    material).
)doc")
      .def("pdf", &pdf, py::arg("wi"), py::arg("wr"), R"doc(The sampling density at reflected directions.

Parameters
----------
wi : array_like, shape (3,)
    Incident unit direction, +z the normal.
wr : array_like, shape (n, 3)
    Reflected unit directions.

Returns
-------
ndarray, shape (n,)
    The density in 1/sr of drawing each wr for wi (it integrates to 1 over the hemisphere).

Raises
------
ValueError
    For wi not a unit vector of 3 values above the horizon, or wr not of shape (n, 3) of unit vectors.
RuntimeError
    As for sample(): f(wi, .) not finite at a cell, or zero at every cell.
)doc")
      .def("__repr__", [](const PySampler& s) {
        return "<icobrdf.Sampler level " + std::to_string(s.sampler.level()) + " of " + s.sampler.source().spec() + ">";
      });
}

}  // namespace icobrdf::python
