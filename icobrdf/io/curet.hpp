#pragma once
// The CURET BRDF database (Dana, van Ginneken, Nayar & Koenderink, "Reflectance and texture of real-world
// surfaces", ACM TOG 18(1), 1999; Columbia's page cs.columbia.edu/CAVE/software/curet/html/brdfm.html) as
// scattered samples.
//
// Two text files, fields separated by runs of blanks, LF or CRLF line ends, a missing final newline accepted:
//   table.txt   G lines `index theta_v phi_v theta_i phi_i`: the geometry of measurement index = 1..G (in
//               order), in radians: the viewing direction (theta_v in [0, pi/2], azimuth phi_v in [-2 pi, 2 pi];
//               the database gives (-pi, pi]), then the illumination direction (theta_i, phi_i), both in the
//               sample's frame (normal +z), both pointing away from the surface. The public table has G = 205
//               (7 camera positions 22.5 deg apart around a fixed lamp, the sample rotated to a fixed grid).
//   abrdf.dat   one line per sample (material): its number (1..61 in the public file), then G values, the BRDF
//               at geometries 1..G, the mean of the database's R, G and B values, in the database's calibrated
//               BRDF unit (1/sr, printed with 3 decimals). Negative values (noise on the dark samples 4 and 61)
//               are kept as measured.
// So sample s at geometry k is f(w_i = (theta_i, phi_i), w_r = (theta_v, phi_v)) = value (w_i towards the
// lamp, w_r towards the camera; icobrdf/core/basis/direction.hpp angles).
// Refused with an InputError naming file:line (expected vs actual): a missing or unreadable file, a field that
// is not a finite number, a wrong field count, an index out of order, an angle out of range (a polar angle
// over pi/2 that fits degrees says so), a repeated sample number. A sample number not in the file is an
// ArgumentError listing the range.
//
// Reciprocal pairs: geometries a != b with theta_v(a) = theta_i(b), theta_i(a) = theta_v(b) and equal
// |phi_v - phi_i| (reduced to [0, pi]) to kCuretReciprocalTolerance; the public table has 29.
#include <Eigen/Core>

#include <string>
#include <utility>
#include <vector>

#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/io/sample_csv.hpp"

namespace icobrdf {

// The public table's reciprocal geometries agree to 1.5e-3 rad (the sample's rotation stage positions); the
// nearest non-reciprocal geometries differ by more than 0.05 rad.
inline constexpr double kCuretReciprocalTolerance = 2e-3;

struct CuretDatabase {
  std::string brdf_path, table_path;
  RowMatrix3d wi, wr;                      // G x 3: illumination and viewing directions (unit vectors)
  std::vector<int> sample_numbers;         // per sample (row of values), as the file numbers them
  Eigen::MatrixXd values;                  // samples x G [1/sr]
  std::vector<std::pair<int, int>> reciprocal_pairs;  // 0-based geometry indices (a < b)
};

CuretDatabase read_curet(const std::string& brdf_path, const std::string& table_path);

// table.txt in the directory of `brdf_path`.
std::string curet_table_beside(const std::string& brdf_path);

// Sample `number` as scattered samples: G samples of weight 1, one channel, `lines` = the geometry index.
BrdfSamples curet_samples(const CuretDatabase& db, int number);

}  // namespace icobrdf
