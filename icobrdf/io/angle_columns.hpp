#pragma once
// The column layouts of CSV files of direction pairs (samples, `--at` files), recognized from the header names,
// and their mapping onto the library's angles (docs/remote-sensing.md has the table).
//
//   theta_i,phi_i,theta_r,phi_r[,values]   the library's own: w_i towards the light, w_r towards the viewer,
//                                          theta from the normal, phi from +x towards +y (docs/conventions.md)
//   sza,vza,raa[,values]                   remote sensing: solar zenith, view zenith, relative azimuth
//                                          raa = vaa - saa. Mapped to w_i = (sza, 0), w_r = (vza, raa).
//   sza,saa,vza,vaa[,values]               solar and view zenith and azimuth, the azimuths those of the sun and
//                                          of the sensor as seen from the surface, clockwise from north
//                                          (compass). Mapped to w_i = (sza, 90 deg - saa), w_r = (vza, 90 deg - vaa):
//                                          x east, y north, z up.
// In both remote-sensing layouts raa = 0 (vaa = saa) puts the sensor on the sun's side: at vza = sza it looks
// along the sun's rays, the hot spot (phase angle 0, cos(xi) = cos sza cos vza + sin sza sin vza cos raa = 1,
// the convention of the Ross-Li kernels, icobrdf/core/models/kernel_models.hpp). raa = 180 deg is forward
// scattering (the specular side). A dataset that counts the view azimuth as the direction the sensor looks in
// (from the sensor to the surface) has raa shifted by 180 deg: convert it before reading.
// A negative zenith is the direction at the opposite azimuth (|theta|, phi + 180 deg): a principal-plane scan
// written as signed vza, e.g. sza = 30, vza = -30, raa = 0 is the specular direction.
// Angle units: degrees unless declared radians (by the reader: an option, a comment, or the suffix _rad on every
// angle column; _deg declares degrees). The suffixes are stripped before the layout is recognized.
// Values: the names decide the quantity. brf, rho, or names beginning brf_ are bidirectional reflectance
// factors (BRF = pi f, read as f = BRF / pi); brdf, f, or names beginning brdf_ are f in 1/sr. Other names are f
// in the library's layout (its long-standing rule) and refused in the remote-sensing layouts (a factor pi
// would be a guess); the option `values=brf|brdf` declares the quantity of every value column, and
// `columns=NAME/NAME/...` replaces the header's names (the same count, in order).
#include <string>
#include <vector>

#include "icobrdf/io/csv.hpp"

namespace icobrdf {

enum class AngleLayout { Library, SunViewRelative, SunViewAzimuths };
enum class ValueQuantity { Brdf, Brf };

struct AngleColumns {
  AngleLayout layout = AngleLayout::Library;
  int angles = 4;                       // leading angle columns: 4, 3 or 4
  ValueQuantity quantity = ValueQuantity::Brdf;
  std::string quantity_declared_by;     // "the column names", "the option values=...", "" (assumed f)
  std::string original_header;          // the header as found, comma-separated (for notes and messages)
  bool unit_suffix_radians = false;     // every angle column carried _rad
  bool unit_suffix_degrees = false;     // every angle column carried _deg
  // The file's name of each library angle column theta_i, phi_i, theta_r, phi_r (for messages; "" for the
  // azimuth the layout does not carry: phi_i of sza,vza,raa is 0).
  std::vector<std::string> file_names;
};

// Options of the reader that concern the columns.
struct AngleColumnOptions {
  std::vector<std::string> names;       // replaces the header's names when not empty (count must match)
  std::string values;                   // "", "brf" or "brdf"
  bool values_expected = true;          // samples have value columns; `--at` files have none
};

// Step 1: applies options.names, strips the unit suffixes of the angle columns and recognizes the layout and
// the values' quantity. InputError (file:1) for a header that names none of the layouts (the message lists
// them), suffixes on some angle columns only or mixed, value names that disagree or are unknown in a
// remote-sensing layout, `names` of the wrong count, or an unknown `values`.
AngleColumns recognize_angle_columns(CsvTable& table, const AngleColumnOptions& options);

// Step 2, once the unit is known: rewrites the table into the library's layout, header theta_i,phi_i,theta_r,
// phi_r followed by the value columns, angles in the file's unit (`radians` says which), BRF values divided by pi.
void to_library_columns(CsvTable& table, const AngleColumns& columns, bool radians);

// "sza,vza,raa", ... : the layout's angle names, for messages.
std::string layout_name(AngleLayout layout);

}  // namespace icobrdf
