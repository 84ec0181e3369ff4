#include "icobrdf/mesh/tessellation.hpp"

#include "icobrdf/mesh/cubature_symmetry.hpp"

#include <array>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/mesh/cell_locator.hpp"
#include "icobrdf/mesh/gnomonic_projection.hpp"
#include "icobrdf/mesh/hemi_lattice.hpp"
#include "icobrdf/mesh/icosahedron.hpp"
#include "icobrdf/mesh/snyder_projection.hpp"
#include "icobrdf/mesh/tessellation_mesh.hpp"
#include "icobrdf/mesh/triangle_rule.hpp"

namespace icobrdf {
namespace {

using Point = HemiLattice::Point;

// A triangular piece of a planar cell lying in one sub-triangle (sub = -1: no splitting).
struct Piece {
  Point a, b, c;
  int sub;
  std::int64_t det;  // area fraction of the face = det / scale^3
};

// Pieces with the face centre as a corner get it as their second corner b: the Stroud rule collapses
// its Gauss-Jacobi direction onto b (a Duffy transform), and around the centre the projection is smooth
// in polar, not in Cartesian, coordinates (its derivatives are singular there), so the rule then sees an
// analytic integrand. The rule is the same; only the corner order of the piece changes.
void fan(const std::vector<Point>& q, int sub, std::int64_t centre, std::vector<Piece>& out) {
  auto is_centre = [&](const Point& p) { return p[0] == centre && p[1] == centre && p[2] == centre; };
  for (size_t t = 1; t + 1 < q.size(); ++t) {
    const std::int64_t d = barycentric_det(q[0], q[t], q[t + 1]);
    if (d <= 0) continue;
    if (is_centre(q[0])) out.push_back({q[t + 1], q[0], q[t], sub, d});
    else if (is_centre(q[t + 1])) out.push_back({q[t], q[t + 1], q[0], sub, d});
    else out.push_back({q[0], q[t], q[t + 1], sub, d});
  }
}

// Cuts a planar cell along the face medians into pieces each inside one sub-triangle (ordering
// l_k >= l_o >= l_m for sub-triangle 2k + t, see icobrdf/mesh/snyder_projection.hpp).
void split_cell(const std::vector<Point>& poly, std::int64_t centre, std::vector<Piece>& out) {
  auto order = [](int s, int& k, int& o, int& m) {
    k = s / 2;
    m = (s % 2 == 0) ? (k + 1) % 3 : (k + 2) % 3;
    o = 3 - k - m;
  };
  for (int s = 0; s < 6; ++s) {
    int k, o, m;
    order(s, k, o, m);
    bool all = true;
    for (const auto& p : poly) all = all && p[k] >= p[o] && p[o] >= p[m];
    if (all) {
      fan(poly, s, centre, out);
      return;
    }
  }
  for (int s = 0; s < 6; ++s) {
    int k, o, m;
    order(s, k, o, m);
    auto q = clip_median(clip_median(poly, k, o), o, m);
    if (q.size() >= 3) fan(q, s, centre, out);
  }
}

std::array<Eigen::Vector3d, 3> corners_of(int f) {
  const auto& v = icosahedron_vertices();
  const auto& h = hemi_icosahedron_faces()[f];
  return {v[h.v[0]], v[h.v[1]], v[h.v[2]]};
}

// Symmetry permutations: the cell containing the image of each cell's interior direction.
void set_symmetry_maps(Grid& g) {
  const int nc = g.cells();
  const CellLocator loc(g.level, to_string(g.kind));
  g.rotate_pi.resize(nc);
  g.mirror_xz.resize(nc);
  g.mirror_yz.resize(nc);
#pragma omp parallel for schedule(static)
  for (int c = 0; c < nc; ++c) {
    const Eigen::Vector3d d = g.directions.row(c).transpose();
    g.rotate_pi[c] = loc.locate(Eigen::Vector3d(-d.x(), -d.y(), d.z()));
    g.mirror_xz[c] = loc.locate(Eigen::Vector3d(d.x(), -d.y(), d.z()));
    g.mirror_yz[c] = loc.locate(Eigen::Vector3d(-d.x(), d.y(), d.z()));
  }
}

}  // namespace

Grid build_equal_area_grid(int level) { return build_hemi_icosahedral_grid(level, GridKind::EqualArea); }
Grid build_equal_area_grid(int level, int degree) { return build_hemi_icosahedral_grid(level, GridKind::EqualArea, degree); }
Grid build_fitting_grid(int level, GridKind kind, bool centre) {
  return centre ? with_centre_cubature(build_hemi_icosahedral_grid(level, kind)) : build_hemi_icosahedral_grid(level, kind, kLutSamplingDegree);
}
Grid build_fitting_grid(int level, const std::string& kind, bool centre) {
  return build_fitting_grid(level, hemi_icosahedral_kind(kind), centre);
}
Grid build_geodesic_grid(int level) { return build_hemi_icosahedral_grid(level, GridKind::Geodesic); }
Grid build_geodesic_grid(int level, int degree) { return build_hemi_icosahedral_grid(level, GridKind::Geodesic, degree); }
Grid build_hemi_icosahedral_grid(int level, const std::string& kind, int degree) {
  return build_hemi_icosahedral_grid(level, hemi_icosahedral_kind(kind), degree);
}

Grid build_hemi_icosahedral_grid(int level, GridKind kind, int degree) {
  const HemiLattice lat(level);
  const TriangleRule rule = stroud_conical_rule(degree);
  const auto tm = build_tessellation_mesh(lat, to_string(kind));  // validates kind
  const bool equal_area = kind == GridKind::EqualArea;
  const auto& mesh = tm->mesh;
  const int nc = lat.cells();
  const double s = static_cast<double>(lat.scale());
  const double s3 = s * s * s;

  Grid g;
  g.kind = kind;
  g.level = level;
  g.cubature_degree = rule.degree;

  // Topology and exact solid angles from the mesh.
  const int nv = static_cast<int>(mesh.n_vertices());
  g.vertices.resize(nv, 3);
  for (int i = 0; i < nv; ++i) {
    const auto& p = mesh.point(TessellationTriMesh::VertexHandle(i));
    g.vertices.row(i) << p[0], p[1], p[2];
  }
  g.faces.resize(nc, 3);
  g.neighbours.resize(nc, 3);
  g.solid_angles.resize(nc);
  g.is_half.resize(nc);
#pragma omp parallel for schedule(static)
  for (int c = 0; c < nc; ++c) {
    const TessellationTriMesh::FaceHandle fh(c);
    int k = 0;
    std::array<TessellationTriMesh::VertexHandle, 3> v;
    for (auto it = mesh.cfv_iter(fh); it.is_valid(); ++it) v[k++] = *it;
    // cfv_iter starts at the face's halfedge target; keep OpenMesh's cyclic order (counter-clockwise).
    for (k = 0; k < 3; ++k) g.faces(c, k) = v[k].idx();
    for (k = 0; k < 3; ++k) {
      const auto he = mesh.find_halfedge(v[(k + 1) % 3], v[(k + 2) % 3]);
      const auto opp = mesh.opposite_halfedge_handle(he);
      g.neighbours(c, k) = mesh.is_boundary(opp) ? -1 : mesh.face_handle(opp).idx();
    }
    g.solid_angles[c] = mesh.property(tm->solid_angle, fh);
    g.is_half[c] = mesh.property(tm->half, fh) ? 1 : 0;
  }

  // Pieces and cubature offsets.
  std::vector<std::int64_t> piece_off(nc + 1, 0);
  std::vector<Piece> pieces;
  pieces.reserve(static_cast<size_t>(nc) * 11 / 10 + 64);
  std::vector<Eigen::Vector3d> centroid(nc);
  for (int c = 0; c < nc; ++c) {
    const auto poly = lat.polygon(c);
    centroid[c] = Eigen::Vector3d::Zero();
    for (const auto& p : poly) centroid[c] += Eigen::Vector3d(p[0], p[1], p[2]) / s;
    centroid[c] /= static_cast<double>(poly.size());
    const std::int64_t centre = lat.scale() / 3;  // scaled barycentric coordinate of the face centre
    if (equal_area) split_cell(poly, centre, pieces);
    else fan(poly, -1, centre, pieces);
    piece_off[c + 1] = static_cast<std::int64_t>(pieces.size());
  }
  const int q = rule.size();
  g.cubature_offsets.resize(nc + 1);
  for (int c = 0; c <= nc; ++c) g.cubature_offsets[c] = piece_off[c] * q;
  const std::int64_t total = g.cubature_offsets[nc];
  g.cubature_points.resize(total, 3);
  g.cubature_weights.resize(total);
  g.directions.resize(nc, 3);

  std::vector<SnyderProjection> snyder;
  std::vector<GnomonicProjection> gnomonic;
  for (int f = 0; f < 12; ++f) {
    if (equal_area) snyder.emplace_back(corners_of(f));
    else gnomonic.emplace_back(corners_of(f));
  }
#pragma omp parallel for schedule(dynamic, 256)
  for (int c = 0; c < nc; ++c) {
    const int f = lat.cell(c).face;
    const Eigen::Vector3d dir = equal_area ? snyder[f].inverse(centroid[c]) : gnomonic[f].inverse(centroid[c]);
    g.directions.row(c) = dir.transpose();
    std::int64_t row = g.cubature_offsets[c];
    double wsum = 0.0;
    for (std::int64_t pi = piece_off[c]; pi < piece_off[c + 1]; ++pi) {
      const Piece& pc = pieces[pi];
      const Eigen::Vector3d a(pc.a[0] / s, pc.a[1] / s, pc.a[2] / s);
      const Eigen::Vector3d ab = Eigen::Vector3d(pc.b[0] - pc.a[0], pc.b[1] - pc.a[1], pc.b[2] - pc.a[2]) / s;
      const Eigen::Vector3d ac = Eigen::Vector3d(pc.c[0] - pc.a[0], pc.c[1] - pc.a[1], pc.c[2] - pc.a[2]) / s;
      const double frac = static_cast<double>(pc.det) / s3;
      for (int k = 0; k < q; ++k, ++row) {
        const Eigen::Vector3d l = a + rule.xi[k] * ab + rule.eta[k] * ac;
        Eigen::Vector3d d;
        double w;
        if (equal_area) {
          d = snyder[f].inverse(l, pc.sub);
          w = rule.weight[k] * frac * SnyderProjection::kFaceArea;
        } else {
          d = gnomonic[f].inverse(l);
          w = rule.weight[k] * frac * gnomonic[f].flat_area() * gnomonic[f].jacobian(l);
        }
        g.cubature_points.row(row) = d.transpose();
        g.cubature_weights[row] = w;
        wsum += w;
      }
    }
    if (!equal_area) {  // rescale to the exact solid angle
      const double scale = g.solid_angles[c] / wsum;
      for (std::int64_t r = g.cubature_offsets[c]; r < g.cubature_offsets[c + 1]; ++r) g.cubature_weights[r] *= scale;
    }
  }

  set_symmetry_maps(g);
  // Symmetry relations of cell averages then hold to rounding (icobrdf/mesh/cubature_symmetry.hpp).
  make_cubature_equivariant(g);
  return g;
}

}  // namespace icobrdf
