#pragma once
// BRDF samples from CSV: one measured (or computed) value per direction pair.
//
//   theta_i,phi_i,theta_r,phi_r,value          one channel
//   theta_i,phi_i,theta_r,phi_r,r,g,b          three channels (names of the value columns are free)
// A header row is required and must begin with theta_i,phi_i,theta_r,phi_r, or with the remote-sensing angles
// sza,vza,raa or sza,saa,vza,vaa (icobrdf/io/angle_columns.hpp: the mapping, BRF or BRDF values by the column
// names); then 1 or 3 value columns.
// Angles in degrees unless radians are declared: by `radians` (the SOURCE option #radians), by the column
// names (theta_i_rad,phi_i_rad,theta_r_rad,phi_r_rad or sza_rad,...; the suffix _deg declares degrees; every angle
// column alike) or by
// a comment line `# units: radians` (or degrees). Declarations that disagree are an InputError.
// theta in [-90, 90] deg, phi in [-360, 360] deg; surface normal +z, phi from +x towards +y, both directions
// pointing away from the surface (icobrdf/core/basis/direction.hpp). A negative theta is signed as NIST writes
// in-plane geometries: (theta, phi) with theta < 0 is the direction (|theta|, phi + 180 deg) (NIST's
// PTFE.data.csv: thetai = -45, phi = 0 puts the source at azimuth 180 deg, phir = 0 the specular side).
// Unit mistakes: with the unit not declared (degrees assumed) and every |theta| <= pi/2, every |phi| <= 2 pi
// (not all theta 0), the file is refused as radians read as degrees (such a fit reaches |f| ~ 1e9: every
// sample within 1.6 deg of the normal); with radians declared, an out-of-range angle's message says when the
// file's angles fit degrees.
// Values f in 1/sr (BRF columns divided by pi); negative values are accepted (measurement noise) and counted.
// Generic CSV rules (BOM, CRLF, '#' comments, blank lines; NaN, Inf, wrong field counts and decimal
// commas refused with file:line) are those of icobrdf/io/csv.hpp. Out-of-range angles: InputError with file:line.
//
// Duplicates: rows naming the same direction pair (equal angles after phi is reduced to [0, 360) deg,
// and set to 0 at theta = 0) are merged into one sample: value = mean of the rows, weight = number of
// rows, so a weighted fit equals the fit of all rows; `duplicates_merged` counts the rows absorbed.
// Reciprocity: a sample (w_i, w_r) whose swapped pair (w_r, w_i) is also present forms a reciprocal
// pair; it is non-reciprocal when |f1 - f2| > tolerance * max(|f1|, |f2|) in some channel. Such pairs
// are counted (with the largest relative difference), or refused (InputError naming both lines) when
// `strict`.
#include <Eigen/Core>

#include <string>
#include <vector>

#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/io/angle_columns.hpp"

namespace icobrdf {

struct SampleCsvOptions {
  bool radians = false;                // declares radians (the option #radians)
  bool strict = false;                 // non-reciprocal pairs are an error
  double reciprocity_tolerance = 1e-6; // relative difference tolerated within a reciprocal pair
  AngleColumnOptions columns;          // the options columns=... and values=...
};

struct BrdfSamples {
  std::string path;
  int channels = 1;
  RowMatrix3d wi, wr;         // S x 3 unit vectors
  Eigen::MatrixXd values;     // S x channels [1/sr]
  Eigen::VectorXd weights;    // S: rows merged into each sample
  std::vector<int> lines;     // S: line of the first row of each sample
  long long rows = 0;                  // data rows read
  long long duplicates_merged = 0;     // rows merged into an earlier sample
  long long reciprocal_pairs = 0;      // samples whose swapped pair is present (each pair counted once)
  long long nonreciprocal_pairs = 0;   // of those, pairs differing beyond the tolerance
  double max_reciprocity_difference = 0.0;  // largest relative difference over reciprocal pairs
  long long negative_values = 0;       // values < 0 (all channels)
  bool plane_of_incidence = false;     // every sample has phi_r = phi_i or phi_i + pi (or a direction at the pole)
  bool radians = false;                // the file's angles were radians
  std::string unit_declared_by;        // what declared the unit ("" when degrees were assumed)
  long long signed_theta_rows = 0;     // rows with a negative theta (a direction at phi + 180 deg)
  AngleLayout layout = AngleLayout::Library;       // the file's angle columns
  ValueQuantity quantity = ValueQuantity::Brdf;    // the file's values (BRF read as f = BRF / pi)
  std::string quantity_declared_by;                // what declared it ("" when f was assumed)
  std::string header;                              // the file's header as found
};

BrdfSamples read_sample_csv(const std::string& path, const SampleCsvOptions& options = {});

}  // namespace icobrdf
