#pragma once
// Albedos of any SOURCE (`icobrdf albedo`, the Python module's albedo functions): black-sky at given solar
// zeniths, white-sky, and the directional albedo curve, per channel, by the quadrature of
// icobrdf/core/models/albedo_quadrature.hpp (definitions, rule and measured accuracy there; docs/albedo.md).
// A LUT file without an albedo asked gives the LUT's own figures instead (icobrdf/pipeline/lut_material.hpp).
//
// Checks: a source without values at some quadrature pairs (a MERL table's empty bins) or with values only at
// its samples (CSV samples) is refused with what to do instead; Inf is refused; a negative albedo is reported
// (refused when strict: icobrdf/pipeline/reflectance_check.hpp).
//
// JSON: {source, channels, channel_names, quadrature: {rule, polar_nodes, azimuth_nodes, sun_polar_nodes,
// sun_azimuths}, white_sky: [per channel], black_sky: [{sza_deg, albedo: [per channel]}], curve: [the same at
// 0, 1, ..., 89 degrees]}; a ross-li model with the ATBD's kernels adds atbd_white_sky and, per black_sky or
// curve entry, atbd_polynomial (icobrdf/core/models/kernel_albedo_polynomial.hpp: an approximation, shown beside).
#include <nlohmann/json.hpp>

#include <ostream>
#include <string>
#include <vector>

#include "icobrdf/core/models/albedo_quadrature.hpp"

namespace icobrdf {

struct AlbedoRequest {
  std::string input;                  // SOURCE, or LUT.h5[#MATERIAL]
  std::vector<double> black_sky_deg;  // solar zeniths [deg], each in [0, 90]
  bool white_sky = false;
  bool curve = false;                 // a(s) at every whole degree from 0 to 89
  bool strict = false;                // a negative albedo is an error, not a warning
  AlbedoRule rule;
};

// Solar zeniths of the curve: 0, 1, ..., kAlbedoCurveLastDeg degrees (90 itself is the horizon, where kernels
// diverge).
inline constexpr int kAlbedoCurveLastDeg = 89;

// True when `request` asks for a LUT's own figures: no albedo asked and the input names an HDF5 file (.h5).
bool asks_lut_albedo(const AlbedoRequest& request);

// The JSON above for a SOURCE (when no albedo is asked: white-sky and the curve), or lut_albedo_json for a LUT.
nlohmann::json albedo_json(const AlbedoRequest& request, std::ostream* warnings);

// The albedos of an opened model (as albedo_json for a SOURCE): `label` and `channel_names` name it.
nlohmann::json model_albedo_json(const BrdfModel& model, const std::string& label, const std::vector<std::string>& channel_names,
                                 const AlbedoRequest& request, std::ostream* warnings);

// The JSON of albedo_json as lines of text for a reader.
std::string albedo_text(const nlohmann::json& albedos);

}  // namespace icobrdf
