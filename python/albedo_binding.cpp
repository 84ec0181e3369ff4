// Albedos from Python (icobrdf/core/models/albedo_quadrature.hpp): icobrdf.black_sky_albedo and
// icobrdf.white_sky_albedo of a Source, a SOURCE text or a Python function of direction pairs, the same as
// methods of Source, and icobrdf.albedo_nodes / icobrdf.white_sky_nodes: the rule's pairs and weights, for
// albedos of BRDF values a user computes as numpy arrays.
#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "icobrdf/core/grid/gauss_legendre.hpp"
#include "icobrdf/core/models/albedo_quadrature.hpp"
#include "icobrdf/core/models/function_model.hpp"
#include "icobrdf/pipeline/source_model.hpp"
#include "python/bindings.hpp"
#include "python/py_source.hpp"

namespace icobrdf::python {
namespace {

constexpr double kDeg = M_PI / 180.0;

AlbedoRule rule_of(int polar_nodes, int azimuth_nodes, int sun_polar_nodes, int sun_azimuths) {
  AlbedoRule r;
  r.polar_nodes = polar_nodes;
  r.azimuth_nodes = azimuth_nodes;
  r.sun_polar_nodes = sun_polar_nodes;
  r.sun_azimuths = sun_azimuths;
  check_albedo_rule(r);
  return r;
}

// A Python function f(wi, wr) -> (n,) or (n, channels) as a model: called with the GIL held, its values checked.
std::shared_ptr<const BrdfModel> model_of_function(py::function f, int channels, bool isotropic) {
  if (channels < 1) throw ArgumentError("channels must be >= 1, found " + std::to_string(channels));
  auto values = [f, channels](const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) {
    py::gil_scoped_acquire hold;
    using Rows = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    const py::object r = f(Rows(wi), Rows(wr));
    const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(r);
    const bool flat = a && a.ndim() == 1 && channels == 1;
    if (!a || !(flat || (a.ndim() == 2 && a.shape(1) == channels)) || a.shape(0) != wi.rows())
      throw ArgumentError("albedo: the function must return " + std::to_string(wi.rows()) + " values" +
                          (channels == 1 ? std::string() : " x " + std::to_string(channels) + " channels") + " as a float array, one row per pair");
    out = Eigen::Map<const Rows>(a.data(), wi.rows(), channels);
  };
  return std::make_shared<FunctionModel>(channels, values, "python function", isotropic, false);
}

// The model behind the first argument: a Source, a SOURCE text, or a callable.
std::shared_ptr<const BrdfModel> model_of(const py::object& source, int channels, bool isotropic) {
  if (py::isinstance<PySource>(source)) return model_of_open_source(source.cast<const PySource&>().source);
  if (py::isinstance<py::str>(source)) {
    std::string label;
    return model_of_source(source.cast<std::string>(), &label);
  }
  if (py::isinstance<py::function>(source)) return model_of_function(source.cast<py::function>(), channels, isotropic);
  throw ArgumentError("albedo: expected a Source, a SOURCE text or a function f(wi, wr), found " + std::string(py::str(source.get_type())));
}

Eigen::MatrixXd black_sky(const py::object& source, const std::vector<double>& sza_deg, int channels, bool isotropic, const AlbedoRule& r) {
  const auto model = model_of(source, channels, isotropic);
  Eigen::VectorXd t(static_cast<Eigen::Index>(sza_deg.size()));
  for (size_t k = 0; k < sza_deg.size(); ++k) t(static_cast<Eigen::Index>(k)) = sza_deg[k] * kDeg;
  py::gil_scoped_release release;
  return black_sky_albedo(*model, t, r);
}

Eigen::VectorXd white_sky(const py::object& source, int channels, bool isotropic, const AlbedoRule& r) {
  const auto model = model_of(source, channels, isotropic);
  py::gil_scoped_release release;
  return white_sky_albedo(*model, r).transpose();
}

using NodeArrays = std::tuple<RowMatrix3d, RowMatrix3d, Eigen::VectorXd>;

NodeArrays albedo_nodes(double sza_deg, double phi_deg, const AlbedoRule& r) {
  const ViewNodes v = black_sky_nodes(sza_deg * kDeg, phi_deg * kDeg, r);
  const Eigen::Vector3d ws(std::sin(sza_deg * kDeg) * std::cos(phi_deg * kDeg), std::sin(sza_deg * kDeg) * std::sin(phi_deg * kDeg),
                           std::cos(sza_deg * kDeg));
  RowMatrix3d wi = ws.transpose().replicate(v.directions.rows(), 1);
  return {wi, v.directions, v.weights};
}

// Every sun node of the white-sky rule (sun azimuth 0): the weights 2 w_k mu_k times the view weights.
NodeArrays white_sky_nodes(const AlbedoRule& r) {
  const QuadratureRule gl = gauss_legendre(r.sun_polar_nodes, 0.0, 1.0);
  std::vector<NodeArrays> parts;
  Eigen::Index n = 0;
  for (Eigen::Index k = 0; k < gl.nodes.size(); ++k) {
    parts.push_back(albedo_nodes(std::acos(gl.nodes(k)) / kDeg, 0.0, r));
    std::get<2>(parts.back()) *= 2.0 * gl.weights(k) * gl.nodes(k);
    n += std::get<2>(parts.back()).size();
  }
  NodeArrays out{RowMatrix3d(n, 3), RowMatrix3d(n, 3), Eigen::VectorXd(n)};
  Eigen::Index at = 0;
  for (const auto& [wi, wr, w] : parts) {
    std::get<0>(out).middleRows(at, w.size()) = wi;
    std::get<1>(out).middleRows(at, w.size()) = wr;
    std::get<2>(out).segment(at, w.size()) = w;
    at += w.size();
  }
  return out;
}

constexpr const char* kRuleParams = R"doc(polar_nodes : int, optional
    Gauss-Legendre nodes per panel of cos(theta_v); the panels split at the sun's cos(theta_s) (default 48).
azimuth_nodes : int, optional
    Gauss-Legendre nodes per half turn of the view azimuth relative to the sun (default 64).
sun_polar_nodes : int, optional
    White-sky: Gauss-Legendre nodes in cos(theta_s) on [0, 1] (default 48).
sun_azimuths : int, optional
    Sources not isotropic by construction: the albedo is the mean over this many sun azimuths (default 16).
)doc";

const std::string kBlackSkyDoc = std::string(R"doc(Black-sky (directional-hemispherical) albedo at solar zeniths.

a(s) = integral over the view hemisphere of f(w_s, w_v) cos(theta_v) dw_v, per channel: for the kernels of
``model:ross-li`` the kernel integrals themselves (iso + vol h_vol(s) + geo h_geo(s)), not divided by pi. Delta
parts add their weight. Accurate to 1e-12 for smooth BRDFs, 4e-6 for the Li-Sparse-R kernel (docs/albedo.md).

Parameters
----------
source : Source, str or callable
    A Source, a SOURCE text, or a function ``f(wi, wr)`` of (n, 3) arrays of unit directions (wi toward the
    sun) returning f [1/sr] as an (n,) or (n, channels) array.
sza_deg : sequence of float
    Solar zeniths in degrees, each in [0, 90].
channels : int, optional
    Channels a function returns (default 1; ignored for a Source or SOURCE text).
isotropic : bool, optional
    Whether a function is unchanged by turns about the normal (default False: mean over the sun azimuths).
)doc") + kRuleParams + R"doc(
Returns
-------
ndarray, shape (len(sza_deg), channels)
    a(s) per zenith and channel (NaN where the source has no value at some quadrature pair).

Raises
------
ValueError
    For a zenith outside [0, 90], a bad node count, or a function returning the wrong shape.
)doc";

const std::string kWhiteSkyDoc = std::string(R"doc(White-sky (bihemispherical) albedo under isotropic illumination.

A = (1/pi) int int f cos(theta_i) cos(theta_v) dw_i dw_v = 2 int_0^{pi/2} a(s) cos(s) sin(s) ds, per channel. For
``model:ross-li`` with unit weights the kernels' integrals (MODIS ATBD: Ross-Thick 0.189184, Li-Sparse-R -1.377622).

Parameters
----------
source : Source, str or callable
    As for ``black_sky_albedo``.
channels : int, optional
    Channels a function returns (default 1).
isotropic : bool, optional
    Whether a function is unchanged by turns about the normal (default False).
)doc") + kRuleParams + R"doc(
Returns
-------
ndarray, shape (channels,)
    A per channel.

Raises
------
ValueError
    For a bad node count or a function returning the wrong shape.
)doc";

const std::string kNodesDoc = std::string(R"doc(The black-sky rule's pairs and weights at one sun direction, for albedos of values computed in numpy.

``weights @ f(wi, wr)`` is the black-sky albedo a(s) of any f given at the pairs.

Parameters
----------
sza_deg : float
    Solar zenith in degrees, in [0, 90].
phi_deg : float, optional
    Solar azimuth in degrees (default 0).
)doc") + kRuleParams + R"doc(
Returns
-------
wi : ndarray, shape (n, 3)
    The sun direction in every row.
wr : ndarray, shape (n, 3)
    The view directions (unit vectors, +z the normal).
weights : ndarray, shape (n,)
    Quadrature weights including cos(theta_v); they sum to pi.

Raises
------
ValueError
    For a zenith outside [0, 90] or a bad node count.
)doc";

const std::string kWhiteNodesDoc = std::string(R"doc(The white-sky rule's pairs and weights (sun azimuth 0), for values computed in numpy.

``weights @ f(wi, wr)`` is the white-sky albedo A of an isotropic f (one sun azimuth; for an anisotropic f, average
over turned copies of the pairs). The weights sum to pi.

Parameters
----------
)doc") + kRuleParams + R"doc(
Returns
-------
wi, wr : ndarray, shape (n, 3)
    Sun and view directions, pair by pair.
weights : ndarray, shape (n,)
    Quadrature weights.

Raises
------
ValueError
    For a bad node count.
)doc";

}  // namespace

void bind_albedo(py::module_& m) {
  m.def(
      "black_sky_albedo",
      [](const py::object& source, const std::vector<double>& sza_deg, int channels, bool isotropic, int pn, int an, int spn, int sa) {
        return black_sky(source, sza_deg, channels, isotropic, rule_of(pn, an, spn, sa));
      },
      py::arg("source"), py::arg("sza_deg"), py::arg("channels") = 1, py::arg("isotropic") = false, py::arg("polar_nodes") = 48,
      py::arg("azimuth_nodes") = 64, py::arg("sun_polar_nodes") = 48, py::arg("sun_azimuths") = 16, kBlackSkyDoc.c_str());
  m.def(
      "white_sky_albedo",
      [](const py::object& source, int channels, bool isotropic, int pn, int an, int spn, int sa) {
        return white_sky(source, channels, isotropic, rule_of(pn, an, spn, sa));
      },
      py::arg("source"), py::arg("channels") = 1, py::arg("isotropic") = false, py::arg("polar_nodes") = 48, py::arg("azimuth_nodes") = 64,
      py::arg("sun_polar_nodes") = 48, py::arg("sun_azimuths") = 16, kWhiteSkyDoc.c_str());
  m.def(
      "albedo_nodes",
      [](double sza_deg, double phi_deg, int pn, int an, int spn, int sa) { return albedo_nodes(sza_deg, phi_deg, rule_of(pn, an, spn, sa)); },
      py::arg("sza_deg"), py::arg("phi_deg") = 0.0, py::arg("polar_nodes") = 48, py::arg("azimuth_nodes") = 64, py::arg("sun_polar_nodes") = 48,
      py::arg("sun_azimuths") = 16, kNodesDoc.c_str());
  m.def(
      "white_sky_nodes", [](int pn, int an, int spn, int sa) { return white_sky_nodes(rule_of(pn, an, spn, sa)); }, py::arg("polar_nodes") = 48,
      py::arg("azimuth_nodes") = 64, py::arg("sun_polar_nodes") = 48, py::arg("sun_azimuths") = 16, kWhiteNodesDoc.c_str());

  auto source = py::reinterpret_borrow<py::class_<PySource>>(m.attr("Source"));
  source.def(
      "black_sky_albedo",
      [](const py::object& self, const std::vector<double>& sza_deg, int pn, int an, int spn, int sa) {
        return black_sky(self, sza_deg, 1, false, rule_of(pn, an, spn, sa));
      },
      py::arg("sza_deg"), py::arg("polar_nodes") = 48, py::arg("azimuth_nodes") = 64, py::arg("sun_polar_nodes") = 48, py::arg("sun_azimuths") = 16,
      R"doc(Black-sky albedo of this source at solar zeniths: ``icobrdf.black_sky_albedo(self, sza_deg, ...)``.

Parameters
----------
sza_deg : sequence of float
    Solar zeniths in degrees, each in [0, 90].
polar_nodes, azimuth_nodes, sun_polar_nodes, sun_azimuths : int, optional
    The rule, as for ``icobrdf.black_sky_albedo``.

Returns
-------
ndarray, shape (len(sza_deg), channels)
    a(s) per zenith and channel.
)doc");
  source.def(
      "white_sky_albedo",
      [](const py::object& self, int pn, int an, int spn, int sa) { return white_sky(self, 1, false, rule_of(pn, an, spn, sa)); },
      py::arg("polar_nodes") = 48, py::arg("azimuth_nodes") = 64, py::arg("sun_polar_nodes") = 48, py::arg("sun_azimuths") = 16,
      R"doc(White-sky albedo of this source: ``icobrdf.white_sky_albedo(self, ...)``.

Parameters
----------
polar_nodes, azimuth_nodes, sun_polar_nodes, sun_azimuths : int, optional
    The rule, as for ``icobrdf.white_sky_albedo``.

Returns
-------
ndarray, shape (channels,)
    A per channel.
)doc");
}

}  // namespace icobrdf::python
