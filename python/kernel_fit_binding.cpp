// sun_view_directions and kernel_fit: remote-sensing geometry and the kernel-driven fit of numpy arrays
// (icobrdf/core/fit/kernel_fit.hpp; conventions in icobrdf/io/angle_columns.hpp and docs/remote-sensing.md).
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <cmath>
#include <optional>
#include <string>
#include <utility>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/fit/kernel_fit.hpp"
#include "python/array_arguments.hpp"
#include "python/bindings.hpp"

namespace icobrdf::python {
namespace {

using Vec = Eigen::Ref<const Eigen::VectorXd>;

// w_i = (sza, 0), w_r = (vza, raa); a negative zenith is the direction at the opposite azimuth.
std::pair<RowMatrix3d, RowMatrix3d> sun_view(const Vec& sza, const Vec& vza, const Vec& raa, bool degrees) {
  const Eigen::Index n = sza.size();
  if (vza.size() != n || raa.size() != n)
    throw ArgumentError("sza, vza, raa: expected arrays of one length, found " + std::to_string(n) + ", " + std::to_string(vza.size()) +
                        ", " + std::to_string(raa.size()));
  const double unit = degrees ? M_PI / 180.0 : 1.0;
  RowMatrix3d wi(n, 3), wr(n, 3);
  for (Eigen::Index k = 0; k < n; ++k) {
    const double s = sza(k) * unit, v = vza(k) * unit, r = raa(k) * unit;
    if (!(std::abs(s) <= M_PI / 2) || !(std::abs(v) <= M_PI / 2) || !std::isfinite(r))
      throw ArgumentError("sun_view_directions: row " + std::to_string(k) + ": zenith angles must lie in [-90, 90] degrees and raa be finite, found sza " +
                          std::to_string(sza(k)) + ", vza " + std::to_string(vza(k)) + ", raa " + std::to_string(raa(k)) +
                          (degrees ? "" : " (radians)"));
    wi.row(k) = direction_from_angles(s, 0.0).transpose();  // sin(-s) = -sin(s): a negative zenith turns by pi
    wr.row(k) = direction_from_angles(v, r).transpose();
  }
  return {wi, wr};
}

}  // namespace

void bind_kernel_fit(py::module_& m) {
  m.def(
      "sun_view_directions",
      [](const Vec& sza, const Vec& vza, const Vec& raa, bool degrees) { return sun_view(sza, vza, raa, degrees); },
      py::arg("sza"), py::arg("vza"), py::arg("raa"), py::arg("degrees") = true,
      R"doc(The library's direction pairs of remote-sensing geometries.

Parameters
----------
sza, vza, raa : array_like, shape (n,)
    Solar zenith, view zenith and relative azimuth raa = vaa - saa (the azimuths of the sun and of the sensor
    seen from the surface). raa = 0 is the sun's side: vza = sza there is the hot spot; raa = 180 degrees is
    forward scattering. A negative zenith is the direction at the opposite azimuth (signed principal-plane
    angles). From compass azimuths pass raa = vaa - saa.
degrees : bool
    Angles in degrees (default) or radians.

Returns
-------
wi, wr : ndarray, shape (n, 3)
    Unit vectors: wi = (sza, azimuth 0) towards the sun, wr = (vza, azimuth raa) towards the sensor, +z the
    normal. The BRDF f in 1/sr of the library relates to the BRF by BRF = pi f.

Raises
------
ValueError
    Arrays of different lengths, a zenith outside [-90, 90] degrees, a non-finite raa.
)doc");
  m.def(
      "kernel_fit",
      [](const Vec& sza, const Vec& vza, const Vec& raa, const Vec& brf, const std::optional<Eigen::VectorXd>& weights, bool degrees,
         const std::string& volume, const std::string& geometric) {
        const auto [wi, wr] = sun_view(sza, vza, raa, degrees);
        if (brf.size() != sza.size())
          throw ArgumentError("kernel_fit: brf has " + std::to_string(brf.size()) + " values for " + std::to_string(sza.size()) + " geometries");
        if (weights && weights->size() != sza.size())
          throw ArgumentError("kernel_fit: weights has " + std::to_string(weights->size()) + " values for " + std::to_string(sza.size()) + " geometries");
        if (volume != "thick" && volume != "thin") throw ArgumentError("kernel_fit: volume expected 'thick' or 'thin', found '" + volume + "'");
        if (geometric != "sparse" && geometric != "dense")
          throw ArgumentError("kernel_fit: geometric expected 'sparse' or 'dense', found '" + geometric + "'");
        KernelChoice kc;
        kc.volume = volume == "thick" ? VolumeKernel::RossThick : VolumeKernel::RossThin;
        kc.geometric = geometric == "sparse" ? GeometricKernel::LiSparseR : GeometricKernel::LiDenseR;
        const Eigen::MatrixXd f = brf / M_PI;
        const Eigen::VectorXd w = weights ? *weights : Eigen::VectorXd::Ones(sza.size());
        KernelFit k;
        {
          py::gil_scoped_release release;
          k = fit_kernel_weights(wi, wr, f, w, kc);
        }
        py::dict d;
        d["weights"] = Eigen::Vector3d(k.weights.col(0));
        d["model"] = "model:" + k.spec(0);
        d["condition"] = k.condition;
        d["determined"] = k.determined;
        d["inverse_gram"] = k.inverse_gram;
        d["noise_sigma"] = k.noise_sigma(0);
        d["residual_rms"] = k.residual_rms(0) * M_PI;
        d["cv_rms"] = k.cv_rms * M_PI;
        d["solar_zenith"] = degrees ? k.solar_zenith * 180.0 / M_PI : k.solar_zenith;
        for (const KernelQuantity& q : k.quantities) {
          py::dict qd;
          qd["value"] = q.value(0);
          qd["sigma"] = q.sigma(0);
          qd["inflation"] = q.inflation;
          qd["u"] = q.u;
          std::string key = q.name;
          for (char& c : key)
            if (c == ' ' || c == '-') c = '_';
          d[key.c_str()] = qd;
        }
        return d;
      },
      py::arg("sza"), py::arg("vza"), py::arg("raa"), py::arg("brf"), py::arg("weights") = py::none(), py::arg("degrees") = true,
      py::arg("volume") = "thick", py::arg("geometric") = "sparse",
      R"doc(Least-squares fit of the three weights of a Ross-Li kernel model to BRF observations.

BRF = iso + vol K_vol(sza, vza, raa) + geo K_geo(sza, vza, raa) (Lucht, Schaaf & Strahler 2000), weighted least
squares, with the weights of determination of Lucht & Lewis (2000): a quantity u = U^T (iso, vol, geo) has the
noise inflation 1/WoD = U^T (K^T W K)^-1 U and the standard error noise_sigma * sqrt(1/WoD).

Parameters
----------
sza, vza, raa : array_like, shape (n,)
    Geometry as for :func:`sun_view_directions` (raa = 0 on the sun's side, the hot spot at vza = sza).
brf : array_like, shape (n,)
    Bidirectional reflectance factors (BRF = pi f: a BRDF f in 1/sr times pi).
weights : array_like, shape (n,), optional
    Non-negative weights (inverse relative variances); all 1 by default.
degrees : bool
    Angles in degrees (default) or radians; also the unit of the returned solar_zenith.
volume, geometric : str
    Kernels: 'thick' or 'thin' (Ross), 'sparse' or 'dense' (Li, reciprocal forms, h/b = 2, b/r = 1).

Returns
-------
dict
    weights : ndarray (3,), iso, vol, geo (BRF units); model : str, the SOURCE of the fitted model;
    condition : float, cond(W^(1/2) K); determined : bool (condition <= 1e6);
    inverse_gram : ndarray (3, 3), (K^T W K)^-1;
    noise_sigma, residual_rms, cv_rms : float, BRF units (5-fold cross-validation, NaN when a fold cannot be fitted);
    solar_zenith : float, the weighted mean solar zenith of the black-sky and nadir quantities;
    white_sky_albedo, black_sky_albedo, nadir_brf : dict with value, sigma, inflation (1/WoD) and u (U).

Raises
------
ValueError
    Arrays of different lengths, angles out of range, non-finite values, negative weights, unknown kernels.
)doc");
}

}  // namespace icobrdf::python
