#include "icobrdf/mesh/tessellation_mesh.hpp"

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <unordered_map>
#include <vector>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/mesh/gnomonic_projection.hpp"
#include "icobrdf/mesh/hemi_lattice.hpp"
#include "icobrdf/mesh/icosahedron.hpp"
#include "icobrdf/mesh/snyder_projection.hpp"

namespace icobrdf {
namespace {

// Canonical integer key of a lattice point (scaled barycentric p on hemi face f): shared points of
// adjacent faces get the same key.
std::uint64_t point_key(int f, const HemiLattice::Point& p) {
  const auto& v = hemi_icosahedron_faces()[f].v;
  int nz = 0, last = -1;
  for (int k = 0; k < 3; ++k)
    if (p[k] != 0) {
      ++nz;
      last = k;
    }
  if (nz == 1) return static_cast<std::uint64_t>(v[last]);
  if (nz == 2) {
    const int z = (p[0] == 0) ? 0 : (p[1] == 0) ? 1 : 2;
    const int a = (z + 1) % 3, b = (z + 2) % 3;
    const int lo = v[a] < v[b] ? a : b, hi = a + b - lo;
    return (1ull << 62) | (static_cast<std::uint64_t>(v[lo]) << 40) | (static_cast<std::uint64_t>(v[hi]) << 32) |
           static_cast<std::uint64_t>(p[lo]);
  }
  return (2ull << 62) | (static_cast<std::uint64_t>(f) << 48) | (static_cast<std::uint64_t>(p[1]) << 24) |
         static_cast<std::uint64_t>(p[2]);
}

std::array<Eigen::Vector3d, 3> mesh_corners_of(int f) {
  const auto& v = icosahedron_vertices();
  const auto& h = hemi_icosahedron_faces()[f];
  return {v[h.v[0]], v[h.v[1]], v[h.v[2]]};
}

}  // namespace

std::unique_ptr<TessellationMesh> build_tessellation_mesh(int level, const std::string& kind) {
  const HemiLattice lat(level);
  return build_tessellation_mesh(lat, kind);
}

GridKind hemi_icosahedral_kind(const std::string& kind) {
  if (kind == to_string(GridKind::EqualArea)) return GridKind::EqualArea;
  if (kind == to_string(GridKind::Geodesic)) return GridKind::Geodesic;
  throw ArgumentError("unknown grid kind '" + kind + "': expected 'equal-area' or 'geodesic'");
}

std::unique_ptr<TessellationMesh> build_tessellation_mesh(const HemiLattice& lat, const std::string& kind) {
  const bool equal_area = hemi_icosahedral_kind(kind) == GridKind::EqualArea;
  const int nc = lat.cells();
  const double s = static_cast<double>(lat.scale());

  // 1. Weld: vertex ids in order of first use (deterministic), with a representative (face, point).
  std::unordered_map<std::uint64_t, int> ids;
  ids.reserve(static_cast<size_t>(nc) * 2);
  std::vector<std::pair<int, HemiLattice::Point>> rep;
  rep.reserve(static_cast<size_t>(nc) / 2 + 64);
  std::vector<std::array<int, 3>> tri(nc);
  for (int c = 0; c < nc; ++c) {
    const auto poly = lat.polygon(c);
    if (poly.size() != 3) throw std::logic_error("tessellation cell " + std::to_string(c) + " is not a triangle");
    const int f = lat.cell(c).face;
    for (int k = 0; k < 3; ++k) {
      const auto key = point_key(f, poly[k]);
      auto [it, fresh] = ids.emplace(key, static_cast<int>(rep.size()));
      if (fresh) rep.emplace_back(f, poly[k]);
      tri[c][k] = it->second;
    }
  }

  // 2. Positions.
  std::vector<SnyderProjection> snyder;
  std::vector<GnomonicProjection> gnomonic;
  for (int f = 0; f < 12; ++f) {
    if (equal_area) snyder.emplace_back(mesh_corners_of(f));
    else gnomonic.emplace_back(mesh_corners_of(f));
  }
  const int nv = static_cast<int>(rep.size());
  std::vector<Eigen::Vector3d> pos(nv);
#pragma omp parallel for schedule(static)
  for (int i = 0; i < nv; ++i) {
    const auto& [f, p] = rep[i];
    int nz = 0, corner = 0;
    for (int k = 0; k < 3; ++k)
      if (p[k] != 0) {
        ++nz;
        corner = k;
      }
    if (nz == 1) {
      pos[i] = mesh_corners_of(f)[corner];
      continue;
    }
    const Eigen::Vector3d l(p[0] / s, p[1] / s, p[2] / s);
    pos[i] = equal_area ? snyder[f].inverse(l) : gnomonic[f].inverse(l);
  }

  // 3. The OpenMesh mesh.
  auto out = std::make_unique<TessellationMesh>();
  out->kind = kind;
  out->level = lat.level();
  auto& mesh = out->mesh;
  mesh.reserve(nv, 3 * static_cast<size_t>(nc) / 2 + nv, nc);
  std::vector<TessellationTriMesh::VertexHandle> vh(nv);
  for (int i = 0; i < nv; ++i) vh[i] = mesh.add_vertex(TessellationTriMesh::Point(pos[i].x(), pos[i].y(), pos[i].z()));
  mesh.add_property(out->cell_id, "cell_id");
  mesh.add_property(out->ico_face, "ico_face");
  mesh.add_property(out->solid_angle, "solid_angle");
  mesh.add_property(out->half, "half");
  const double whole = SnyderProjection::kFaceArea / (static_cast<double>(lat.n()) * lat.n());
  for (int c = 0; c < nc; ++c) {
    const auto fh = mesh.add_face(vh[tri[c][0]], vh[tri[c][1]], vh[tri[c][2]]);
    if (!fh.is_valid() || fh.idx() != c)
      throw std::logic_error("OpenMesh rejected tessellation cell " + std::to_string(c));
    const auto& cl = lat.cell(c);
    mesh.property(out->cell_id, fh) = c;
    mesh.property(out->ico_face, fh) = cl.face;
    mesh.property(out->half, fh) = cl.half;
    mesh.property(out->solid_angle, fh) =
        equal_area ? (cl.half ? 0.5 * whole : whole)
                   : spherical_triangle_solid_angle(pos[tri[c][0]], pos[tri[c][1]], pos[tri[c][2]]);
  }
  return out;
}

}  // namespace icobrdf
