// The Python module `icobrdf` (pybind11): the library's matrix BRDF operations on numpy arrays.
//
// Conventions are the library's: directions are unit vectors (n x 3 float64 arrays, +z the normal,
// z >= 0), w_i points toward the light; f is in 1/sr; coefficient matrices are M x M, M = (N+1)(N+2)/2, in
// ANSI order (docs/api.md). Arrays passed in are copied into the library's types (row-major n x 3 for
// directions); arrays returned are new numpy arrays owned by Python. Long calls release the GIL.
// Errors map to Python exceptions: ValueError (bad arguments), OSError (files), RuntimeError (input data,
// unsupported requests, resources), MemoryError.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "icobrdf/blas/blas_dense_kernels.hpp"
#include "icobrdf/core/projection/discrete_basis.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/helmholtz_modes.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/core/basis/lowpass_filter.hpp"
#include "icobrdf/core/projection/lut.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/projection/projection.hpp"
#include "icobrdf/core/spectrum/spectrum_ops.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/material_sampler.hpp"
#include "icobrdf/io/spectrum_file.hpp"
#include "icobrdf/mesh/tessellation.hpp"
#include "icobrdf/pipeline/fit_source.hpp"

namespace py = pybind11;
using namespace icobrdf;

namespace {

// Directions from any (n, 3) array: the library's row-major type.
RowMatrix3d directions(const Eigen::Ref<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>& a,
                       const char* what) {
  if (a.cols() != 3) throw ArgumentError(std::string(what) + ": expected an (n, 3) array of unit vectors, found (" +
                                         std::to_string(a.rows()) + ", " + std::to_string(a.cols()) + ")");
  return a;
}
using DirArray = Eigen::Ref<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>;

// Pairs per chunk when evaluating from numpy arrays: the directions are copied into reused row-major
// buffers of this many rows (6 MB each) instead of whole new copies, whose first touch cost a third of the
// evaluation at 10^6 pairs. Measured at 2^20 pairs, order 8, 2 threads: chunks of 2^16 reach 0.50 of the
// C++ rate (each call's threads get too little work), 2^18 0.94, one whole copy 0.65.
constexpr Eigen::Index kEvalChunk = Eigen::Index{1} << 18;

// fn(wi_chunk, wr_chunk) -> rows x cols values, applied chunk by chunk into one result.
template <class Fn>
Eigen::MatrixXd eval_chunked(const DirArray& wi, const DirArray& wr, Eigen::Index cols, Fn fn) {
  if (wi.cols() != 3 || wr.cols() != 3)
    throw ArgumentError(std::string(wi.cols() != 3 ? "wi" : "wr") + ": expected an (n, 3) array of unit vectors, found (" +
                        std::to_string(wi.cols() != 3 ? wi.rows() : wr.rows()) + ", " + std::to_string(wi.cols() != 3 ? wi.cols() : wr.cols()) + ")");
  if (wi.rows() != wr.rows())
    throw ArgumentError("eval: wi has " + std::to_string(wi.rows()) + " rows, wr has " + std::to_string(wr.rows()));
  const Eigen::Index n = wi.rows();
  Eigen::MatrixXd out(n, cols);
  py::gil_scoped_release release;
  RowMatrix3d a, b;
  for (Eigen::Index r0 = 0; r0 < n; r0 += kEvalChunk) {
    const Eigen::Index m = std::min(kEvalChunk, n - r0);
    a = wi.middleRows(r0, m);
    b = wr.middleRows(r0, m);
    out.middleRows(r0, m) = fn(a, b);
  }
  return out;
}

// A source opened once and shared by the Python object.
struct PySource {
  std::shared_ptr<BrdfSource> source;
};

PySource open(const std::string& text) { return {std::shared_ptr<BrdfSource>(open_source(text))}; }

Eigen::MatrixXd eval_source(const BrdfSource& s, const DirArray& wi, const DirArray& wr) {
  return eval_chunked(wi, wr, s.channels(), [&s](const RowMatrix3d& a, const RowMatrix3d& b) { return s.eval(a, b); });
}

Spectrum fit(const PySource& src, int level, int order, bool isotropic, bool cosine, const std::string& filter,
             const std::string& sampling, double gram_tolerance) {
  FitRequest r;
  r.level = level;
  r.order = order;
  r.isotropic = isotropic;
  r.cosine = cosine;
  r.filter = parse_lowpass_filter(filter);
  r.gram_tolerance = gram_tolerance;
  const auto s = lut_sampling_named(sampling);
  if (!s) throw ArgumentError("sampling: expected 'average' or 'centre', found '" + quoted_text(sampling) + "'");
  r.sampling = *s;
  py::gil_scoped_release release;
  return fit_source(*src.source, r).spectrum;
}

std::vector<Eigen::MatrixXd> lut_of(const std::string& model_spec, const Grid& grid, bool cosine, const std::string& sampling) {
  const auto model = parse_model_source(model_spec);
  const auto s = lut_sampling_named(sampling);
  if (!s) throw ArgumentError("sampling: expected 'average' or 'centre', found '" + quoted_text(sampling) + "'");
  py::gil_scoped_release release;
  return build_lut(*model, grid, cosine || !model->delta_parts().empty(), *s).channels;
}

// Importance sampling from a source: the MaterialSampler plus the source it keeps alive.
struct PySampler {
  MaterialSampler sampler;
};

PySampler make_sampler(const PySource& src, int level, const std::string& cell_value) {
  const auto s = lut_sampling_named(cell_value);
  if (!s) throw ArgumentError("cell_value: expected 'centre' or 'average', found '" + quoted_text(cell_value) + "'");
  py::gil_scoped_release release;
  return PySampler{MaterialSampler(src.source, level, *s)};
}

Eigen::Vector3d incident_direction(const Eigen::Ref<const Eigen::VectorXd>& wi) {
  if (wi.size() != 3) throw ArgumentError("wi: expected a unit vector of 3 values, found " + std::to_string(wi.size()) + " values");
  return wi;
}

}  // namespace

PYBIND11_MODULE(icobrdf, m) {
  m.doc() = "icobrdf: BRDFs as exact linear algebra on an equal-area icosahedral hemisphere tessellation";
  m.attr("__version__") = ICOBRDF_VERSION;
  set_default_dense_kernels(&fit_dense_kernels());  // the sample fits' kernels, as in the icobrdf program

  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const ArgumentError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const IoError& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    } catch (const ResourceError& e) {
      PyErr_SetString(PyExc_MemoryError, e.what());
    } catch (const InputError& e) {
      PyErr_SetString(PyExc_RuntimeError, e.what());
    } catch (const UnsupportedError& e) {
      PyErr_SetString(PyExc_RuntimeError, e.what());
    }
  });

  // ---- grids
  py::class_<Grid>(m, "Grid", "An equal-area (or geodesic) hemi-icosahedral tessellation of the upper hemisphere")
      .def_static("equal_area", [](int level) { return build_equal_area_grid(level); }, py::arg("level"),
                  "The equal-area grid of `level` (0..8): 10*4^L + 2^(L+1) cells")
      .def_static("geodesic", [](int level) { return build_geodesic_grid(level); }, py::arg("level"))
      .def_property_readonly("level", [](const Grid& g) { return g.level; })
      .def_property_readonly("cells", &Grid::cells)
      .def_property_readonly("directions", [](const Grid& g) { return Eigen::MatrixXd(g.directions); },
                             "cells x 3 representative direction of each cell")
      .def_property_readonly("solid_angles", [](const Grid& g) { return Eigen::VectorXd(g.solid_angles); }, "cells, sr")
      .def("__repr__", [](const Grid& g) {
        return "<icobrdf.Grid " + std::string(to_string(g.kind)) + " level " + std::to_string(g.level) + ", " +
               std::to_string(g.cells()) + " cells>";
      });

  // ---- basis and modes
  m.def("basis_count", &hemisphere_basis_count, py::arg("order"), "M = (N+1)(N+2)/2 hemisphere functions of order N");
  m.def("hemisphere_basis",
        [](int order, const DirArray& dirs) {
          const RowMatrix3d d = directions(dirs, "dirs");
          py::gil_scoped_release release;
          return hemisphere_basis_matrix(order, d);
        },
        py::arg("order"), py::arg("dirs"), "K_j(w) for j < M at n directions: n x M (orthonormal on the hemisphere)");
  m.def("helmholtz_modes",
        [](int order, const DirArray& wi, const DirArray& wr) {
          const RowMatrix3d a = directions(wi, "wi"), b = directions(wr, "wr");
          py::gil_scoped_release release;
          return helmholtz_modes_eval(order, a, b);
        },
        py::arg("order"), py::arg("wi"), py::arg("wr"), "Values of every Helmholtz (BSSS) mode at n pairs: n x modes");
  m.def("isotropic_modes",
        [](int order, const DirArray& wi, const DirArray& wr) {
          const RowMatrix3d a = directions(wi, "wi"), b = directions(wr, "wr");
          py::gil_scoped_release release;
          return isotropic_modes_eval(order, a, b);
        },
        py::arg("order"), py::arg("wi"), py::arg("wr"), "Values of every isotropic (IBSSS) mode at n pairs: n x modes");

  // ---- sources
  py::class_<PySource>(m, "Source",
                       "A SOURCE: model:NAME[:key=value,...], FILE.h5[#MATERIAL] (spectrum or bank), a MERL table, an RGL "
                       ".bsdf file, CSV samples or a SCATMECH coefficient file")
      .def(py::init(&open), py::arg("text"))
      .def_property_readonly("spec", [](const PySource& s) { return s.source->spec(); })
      .def_property_readonly("channels", [](const PySource& s) { return s.source->channels(); })
      .def_property_readonly("has_delta", [](const PySource& s) { return s.source->has_delta(); })
      .def("eval", [](const PySource& s, const DirArray& wi, const DirArray& wr) { return eval_source(*s.source, wi, wr); },
           py::arg("wi"), py::arg("wr"), "f [1/sr] at n direction pairs: n x channels")
      .def("__repr__", [](const PySource& s) { return "<icobrdf.Source " + s.source->spec() + ">"; });
  py::class_<PySampler>(m, "Sampler",
                        "Importance sampling of reflected directions from a Source (icobrdf/io/material_sampler.hpp): "
                        "p_k proportional to max(f, 0) cos A_k over the equal-area cells of `level`, uniform in solid "
                        "angle inside the drawn cell")
      .def(py::init(&make_sampler), py::arg("source"), py::arg("level") = kDefaultSamplingLevel, py::arg("cell_value") = "centre",
           "cell_value: 'centre' (f at each cell's direction) or 'average' (degree-2 cubature over each cell)")
      .def_property_readonly("level", [](const PySampler& s) { return s.sampler.level(); })
      .def(
          "sample",
          [](const PySampler& s, const Eigen::Ref<const Eigen::VectorXd>& wi, const Eigen::VectorXd& u1, const Eigen::VectorXd& u2) {
            const Eigen::Vector3d w = incident_direction(wi);
            MaterialSamples out;
            {
              py::gil_scoped_release release;
              out = s.sampler.sample(w, u1, u2);
            }
            return py::make_tuple(Eigen::MatrixXd(out.directions), out.pdf, out.weight);
          },
          py::arg("wi"), py::arg("u1"), py::arg("u2"),
          "Draws for incident direction wi (3,) from uniform numbers u1, u2 (n,) in [0, 1]: (wr (n, 3), pdf (n,) [1/sr], "
          "weight (n, channels) = f cos(theta_r) / pdf)")
      .def(
          "pdf",
          [](const PySampler& s, const Eigen::Ref<const Eigen::VectorXd>& wi, const DirArray& wr) {
            const Eigen::Vector3d w = incident_direction(wi);
            const RowMatrix3d r = directions(wr, "wr");
            py::gil_scoped_release release;
            return s.sampler.pdf(w, r);
          },
          py::arg("wi"), py::arg("wr"), "The sampling density [1/sr] at directions wr (n, 3) for incident direction wi (3,)")
      .def("__repr__", [](const PySampler& s) {
        return "<icobrdf.Sampler level " + std::to_string(s.sampler.level()) + " of " + s.sampler.source().spec() + ">";
      });
  m.def("models", [] {
    std::vector<std::string> names;
    for (const auto& info : model_registry()) names.push_back(info.name);
    return names;
  }, "Names of the analytic models");

  // ---- spectra
  py::class_<Spectrum>(m, "Spectrum", "Coefficients of a BRDF in the hemisphere basis: one symmetric M x M matrix per channel")
      .def_readonly("order", &Spectrum::order)
      .def_readonly("isotropic", &Spectrum::isotropic)
      .def_readonly("cosine", &Spectrum::cosine, "coefficients of g = f cos(theta_i) instead of f")
      .def_readonly("source", &Spectrum::source)
      .def_readonly("level", &Spectrum::level)
      .def_readonly("filter", &Spectrum::filter)
      .def_readonly("gram_error", &Spectrum::gram_error)
      .def_readonly("max_albedo", &Spectrum::max_albedo)
      .def_property_readonly("coefficients", [](const Spectrum& s) { return s.channels; })
      .def_readonly("channel_names", &Spectrum::channel_names, "labels of the channels (RGB or wavelengths); empty when unlabelled")
      .def("eval",
           [](const Spectrum& s, const DirArray& wi, const DirArray& wr) {
             const auto src = spectrum_source(s);
             return eval_source(*src, wi, wr);
           },
           py::arg("wi"), py::arg("wr"), "f [1/sr] of the expansion at n pairs: n x channels")
      .def("__repr__", [](const Spectrum& s) {
        return "<icobrdf.Spectrum order " + std::to_string(s.order) + ", " + std::to_string(s.channel_count()) + " channel(s) of " +
               s.source + ">";
      });
  m.def("fit", &fit, py::arg("source"), py::arg("level") = 4, py::arg("order") = 8, py::arg("isotropic") = false,
        py::arg("cosine") = false, py::arg("filter") = "none", py::arg("sampling") = "average",
        py::arg("gram_tolerance") = kDefaultGramTolerance,
        "Project a source onto the modes on the equal-area grid of `level`, to `order` (as `icobrdf fit`)");
  m.def("read_spectrum", [](const std::string& path, const std::string& name) { return read_spectrum_file(path, name); },
        py::arg("path"), py::arg("material") = "", "The spectrum of a material of a spectrum file or bank");
  m.def("write_spectrum",
        [](const std::string& path, const Spectrum& s, const std::string& name) { write_spectrum_file(path, s, nullptr, name); },
        py::arg("path"), py::arg("spectrum"), py::arg("material") = "material", "Write a spectrum file (atomically)");
  m.def("bank_materials",
        [](const std::string& path) {
          std::vector<std::string> names;
          for (const auto& mat : read_bank(path, ReadOptions{.read_luts = false}).materials) names.push_back(mat.name);
          return names;
        },
        py::arg("path"), "Names of the materials of a bank or spectrum file");

  // ---- LUTs and operators
  m.def("lut", &lut_of, py::arg("model"), py::arg("grid"), py::arg("cosine") = false, py::arg("sampling") = "average",
        "cells x cells LUT of a model per channel (f, or g = f cos(theta_i) when cosine)");
  py::class_<DiscreteBasis>(m, "DiscreteBasis", "The basis sampled on a grid: B (cells x M cell averages), W, G = B^T W B")
      .def(py::init([](const Grid& g, int order) {
             py::gil_scoped_release release;
             return build_discrete_basis(g, order);
           }),
           py::arg("grid"), py::arg("order"))
      .def_readonly("order", &DiscreteBasis::order)
      .def_readonly("B", &DiscreteBasis::B)
      .def_readonly("W", &DiscreteBasis::W)
      .def_readonly("G", &DiscreteBasis::G)
      .def_readonly("gram_error", &DiscreteBasis::gram_error)
      .def_readonly("condition", &DiscreteBasis::condition)
      .def("check_supported", [](const DiscreteBasis& b, double tol) { check_supported(b, tol); }, py::arg("tolerance") = kDefaultGramTolerance,
           "Raise RuntimeError when the grid does not resolve the order (Gram error above the tolerance)");
  py::class_<ProjectionOperator>(m, "Projection", "P = W B G^-1 (cells x M): C = P^T F P")
      .def(py::init([](const DiscreteBasis& b) { return make_projection(b); }), py::arg("basis"))
      .def_readonly("P", &ProjectionOperator::P);
  m.def("project",
        [](const ProjectionOperator& p, const Eigen::MatrixXd& lut) {
          py::gil_scoped_release release;
          return project_lut(p, lut);
        },
        py::arg("projection"), py::arg("lut"), "C = P^T F P");
  m.def("reconstruct",
        [](const DiscreteBasis& b, const Eigen::MatrixXd& c) {
          py::gil_scoped_release release;
          return reconstruct_lut(b, c);
        },
        py::arg("basis"), py::arg("coefficients"), "F = B C B^T");
  m.def("smooth",
        [](const DiscreteBasis& b, const ProjectionOperator& p, const Eigen::MatrixXd& lut, const std::string& filter) {
          const LowPassFilter f = parse_lowpass_filter(filter);
          py::gil_scoped_release release;
          return smooth_lut(b, p, lut, f);
        },
        py::arg("basis"), py::arg("projection"), py::arg("lut"), py::arg("filter") = "none", "S F S^T with S = B P^T (filtered)");
  m.def("evaluate_coefficients",
        [](const Eigen::MatrixXd& c, int order, const DirArray& wi, const DirArray& wr) {
          const Eigen::MatrixXd f = eval_chunked(wi, wr, 1, [&](const RowMatrix3d& a, const RowMatrix3d& b) {
            return Eigen::MatrixXd(evaluate_coefficients(c, order, a, b));
          });
          return Eigen::VectorXd(f.col(0));
        },
        py::arg("coefficients"), py::arg("order"), py::arg("wi"), py::arg("wr"), "sum_ab C_ab K_a(w_i) K_b(w_r) at n pairs");
}
