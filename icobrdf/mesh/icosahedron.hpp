#pragma once
// The regular icosahedron in the orientation used by the hemisphere tessellation.
//
// Vertices: (0, +-1, +-phi), (+-1, +-phi, 0), (+-phi, 0, +-1), normalized (phi = golden ratio). The z axis
// is a 2-fold axis (through the midpoint of the edge (0, +-1, phi)), and the planes z = 0, x = 0, y = 0 are
// mirror planes. The upper hemisphere z >= 0 holds 8 whole faces plus 4 faces cut in half by the equator
// along one of their medians (the median from their equatorial vertex).
#include <Eigen/Core>

#include <array>
#include <vector>

namespace icobrdf {

// The 12 unit vertices, in the order (0,+-1,+-phi), (+-1,+-phi,0), (+-phi,0,+-1) with the sign pattern
// (+,+), (+,-), (-,+), (-,-).
const std::vector<Eigen::Vector3d>& icosahedron_vertices();

// The 20 faces as vertex-id triples, counter-clockwise seen from outside.
const std::vector<std::array<int, 3>>& icosahedron_faces();

// A face of the hemi-icosahedron (the faces meeting z > 0).
struct HemiFace {
  std::array<int, 3> v;          // vertex ids, counter-clockwise seen from outside
  Eigen::Vector3d centre;        // unit vector through the face centre
  bool bisected = false;         // cut in half by the equator
  // For a bisected face: v[0] lies on the equator and the median lambda_1 = lambda_2 (barycentric
  // coordinates with respect to v) lies on the equator; upper_corner (1 or 2) is the corner with z > 0.
  int upper_corner = 0;
};

// The 12 faces of the hemi-icosahedron in a fixed order: by decreasing centre height, then by azimuth
// of the centre in [0, 2 pi). Whole faces start at their lowest vertex id; bisected faces at their
// equatorial vertex.
const std::vector<HemiFace>& hemi_icosahedron_faces();
// The unit corner vectors of hemi-icosahedron face `face` (0..11), in the order of HemiFace::v.
std::array<Eigen::Vector3d, 3> hemi_face_corners(int face);

}  // namespace icobrdf
