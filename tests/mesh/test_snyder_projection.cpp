// Snyder equal-area projection of an icosahedron face: round trips, area preservation measured by finite
// differences (independent of the construction's own area argument), continuity across sub-triangle
// boundaries and face edges, and the geometry constant a = arc CM.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <random>

#include "icobrdf/mesh/icosahedron.hpp"
#include "icobrdf/mesh/snyder_projection.hpp"
#include "tests/support/unity_id.hpp"

using namespace icobrdf;

namespace ICOBRDF_UNITY_ID {
// Round trips through closed forms: a few ulps per step; 1e-14 is the required bound.
constexpr double kRoundTripTol = 1e-14;
// Richardson-extrapolated central differences (h = 1e-3) away from the face centre: truncation ~1e-9,
// rounding ~1e-13 / h; 1e-7 relative leaves a margin while a real area distortion would be >= 1e-3.
constexpr double kJacobianRelTol = 1e-7;
// Points computed from two faces / sub-triangles agree to rounding.
constexpr double kContinuityTol = 1e-15 * 4;

std::array<Eigen::Vector3d, 3> corners(int f) {
  const auto& v = icosahedron_vertices();
  const auto& h = hemi_icosahedron_faces()[f];
  return {v[h.v[0]], v[h.v[1]], v[h.v[2]]};
}

Eigen::Vector3d random_bary(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  double a = u(rng), b = u(rng);
  if (a + b > 1) {
    a = 1 - a;
    b = 1 - b;
  }
  return Eigen::Vector3d(1 - a - b, a, b);
}

TEST(SnyderProjection, ArcCentreMidpointMatchesRightTriangle) {
  // Right spherical triangle C M V with angles 60 deg at C, 36 deg at V (5 faces meet at a vertex),
  // 90 deg at M: cos(CM) = cos(36 deg) / sin(60 deg) (Napier).
  const SnyderProjection p(corners(0));
  EXPECT_NEAR(p.arc_centre_midpoint(), std::acos(std::cos(M_PI / 5) / std::sin(M_PI / 3)), 1e-15);
  // and the actual arc from every face centre to its edge midpoints
  for (int f = 0; f < 12; ++f) {
    const auto c = corners(f);
    const Eigen::Vector3d centre = (c[0] + c[1] + c[2]).normalized();
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d m = (c[(k + 1) % 3] + c[(k + 2) % 3]).normalized();
      EXPECT_NEAR(std::atan2(centre.cross(m).norm(), centre.dot(m)), p.arc_centre_midpoint(), 1e-15);
    }
  }
  // Planar face area = spherical face area: 3 sqrt(3) r^2 = 4 pi / 20.
  EXPECT_NEAR(3 * std::sqrt(3.0) * p.inradius() * p.inradius(), 4 * M_PI / 20, 1e-15);
}

TEST(SnyderProjection, RoundTripsAreIdentityTo1e14) {
  std::mt19937_64 rng(7);
  double e_plane = 0, e_sphere = 0;
  for (int f = 0; f < 12; ++f) {
    const SnyderProjection p(corners(f));
    std::vector<Eigen::Vector3d> pts;
    for (int k = 0; k < 4000; ++k) pts.push_back(random_bary(rng));
    // Hard cases: the centre, corners, edge midpoints, on the medians, near the centre, on edges.
    pts.push_back(Eigen::Vector3d(1, 1, 1) / 3);
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      c[k] = 1;
      pts.push_back(c);
      Eigen::Vector3d m = Eigen::Vector3d::Constant(0.5);
      m[k] = 0;
      pts.push_back(m);
      for (double t : {1e-12, 1e-6, 0.1, 0.3, 0.49}) {
        Eigen::Vector3d q = Eigen::Vector3d::Constant(t);
        q[k] = 1 - 2 * t;
        pts.push_back(q);  // on the median through corner k
        Eigen::Vector3d e = Eigen::Vector3d::Zero();
        e[(k + 1) % 3] = t;
        e[(k + 2) % 3] = 1 - t;
        pts.push_back(e);  // on an edge
        pts.push_back(Eigen::Vector3d(1, 1, 1) / 3 + t * 1e-6 * (c - Eigen::Vector3d(1, 1, 1) / 3));
      }
    }
    for (const auto& l : pts) {
      const Eigen::Vector3d d = p.inverse(l);
      EXPECT_NEAR(d.norm(), 1.0, kRoundTripTol);
      const Eigen::Vector3d l2 = p.forward(d);
      e_plane = std::max(e_plane, (l2 - l).cwiseAbs().maxCoeff());
      e_sphere = std::max(e_sphere, (p.inverse(l2) - d).cwiseAbs().maxCoeff());
    }
  }
  RecordProperty("max_plane_roundtrip_error", std::to_string(e_plane));
  RecordProperty("max_sphere_roundtrip_error", std::to_string(e_sphere));
  std::printf("projection round trips: plane->sphere->plane %.3g, sphere->plane->sphere %.3g\n", e_plane, e_sphere);
  EXPECT_LT(e_plane, kRoundTripTol);
  EXPECT_LT(e_sphere, kRoundTripTol);
}

TEST(SnyderProjection, AreaElementEqualsPlanarAreaByFiniteDifferences) {
  // Parametrize l = l0 + s (-1, 1, 0) + t (-1, 0, 1): the planar parallelogram spanned by ds, dt has area
  // 2 * (planar face area) ds dt. The spherical area element |d_s x d_t| must be the same. Central
  // differences with one Richardson step (truncation O(h^4 / rho^4), rho = distance from the centre, where
  // the polar construction has its singular derivatives); points within 0.05 of the centre are skipped.
  std::mt19937_64 rng(11);
  const double h = 1e-3;
  const Eigen::Vector3d es(-1, 1, 0), et(-1, 0, 1), centre = Eigen::Vector3d::Constant(1.0 / 3.0);
  double worst = 0;
  int tested = 0;
  for (int f = 0; f < 12; ++f) {
    const SnyderProjection p(corners(f));
    for (int k = 0; k < 300; ++k) {
      const Eigen::Vector3d l = random_bary(rng);
      if ((l - centre).cwiseAbs().maxCoeff() < 0.05 || l.minCoeff() < 4 * h) continue;
      const int sub = SnyderProjection::sub_triangle(l);  // differentiate the smooth piece of sub-triangle sub
      auto jac = [&](double hh) {
        const Eigen::Vector3d ds = (p.inverse(l + hh * es, sub) - p.inverse(l - hh * es, sub)) / (2 * hh);
        const Eigen::Vector3d dt = (p.inverse(l + hh * et, sub) - p.inverse(l - hh * et, sub)) / (2 * hh);
        return ds.cross(dt).norm() / (2 * SnyderProjection::kFaceArea);
      };
      const double ratio = (4 * jac(h / 2) - jac(h)) / 3;
      worst = std::max(worst, std::abs(ratio - 1));
      ++tested;
    }
  }
  std::printf("area element |dOmega/dA - 1| max %.3g over %d points\n", worst, tested);
  EXPECT_GT(tested, 3000);
  EXPECT_LT(worst, kJacobianRelTol);
}

TEST(SnyderProjection, ContinuousAcrossSubTrianglesAndFaceEdges) {
  // On a median both adjacent sub-triangles give the same point.
  const SnyderProjection p(corners(0));
  for (int k = 0; k < 3; ++k)
    for (double t : {0.05, 0.2, 0.33, 0.45}) {
      Eigen::Vector3d q = Eigen::Vector3d::Constant(t);
      q[k] = 1 - 2 * t;
      // q lies on the boundary between sub-triangles 2k and 2k+1 (t < 1/3) or between sub-triangles of the
      // two other corners' midpoint side (t > 1/3): evaluate all sub-triangles whose closure contains q.
      Eigen::Vector3d ref = p.inverse(q);
      for (int s = 0; s < 6; ++s) {
        const int kk = s / 2, m = (s % 2 == 0) ? (kk + 1) % 3 : (kk + 2) % 3, o = 3 - kk - m;
        if (q[kk] >= q[o] - 1e-15 && q[o] >= q[m] - 1e-15) {
          EXPECT_LT((p.inverse(q, s) - ref).norm(), kContinuityTol);
        }
      }
    }
  // Shared icosahedron edges: the same sphere point from both faces.
  const auto& v = icosahedron_vertices();
  const auto& hf = hemi_icosahedron_faces();
  int shared = 0;
  for (int f = 0; f < 12; ++f)
    for (int g = f + 1; g < 12; ++g)
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
          // edge (v_a, v_{a+1}) of f equals (v_{b+1}, v_b) of g
          if (hf[f].v[a] != hf[g].v[(b + 1) % 3] || hf[f].v[(a + 1) % 3] != hf[g].v[b]) continue;
          ++shared;
          const SnyderProjection pf(corners(f)), pg(corners(g));
          for (double t : {0.0, 0.1, 0.25, 0.5, 0.7, 1.0}) {
            Eigen::Vector3d lf = Eigen::Vector3d::Zero(), lg = Eigen::Vector3d::Zero();
            lf[a] = 1 - t;
            lf[(a + 1) % 3] = t;
            lg[(b + 1) % 3] = 1 - t;
            lg[b] = t;
            const Eigen::Vector3d df = pf.inverse(lf), dg = pg.inverse(lg);
            EXPECT_LT((df - dg).norm(), kContinuityTol) << f << " " << g << " " << t;
            // and the point lies on the great circle of the edge
            EXPECT_NEAR(df.dot(v[hf[f].v[a]].cross(v[hf[f].v[(a + 1) % 3]])), 0.0, kContinuityTol);
          }
        }
  // 12 faces x 3 sides, minus 2 whole equatorial edges and the 4 edges of the bisected faces leading to their
  // lower corner (shared with lower faces), counted twice: (36 - 6) / 2.
  EXPECT_EQ(shared, 15);
}

TEST(SnyderProjection, SubTriangleTableMatchesDefinition) {
  // Reference: corner k = first argmax, midpoint m = argmin of the other two (the later one on ties),
  // index 2k + (m == k+1 mod 3 ? 0 : 1). All orderings including ties (values from {0, 1, 2}).
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      for (int c = 0; c < 3; ++c) {
        const double g[3] = {double(a), double(b), double(c)};
        int k = 0;
        for (int i = 1; i < 3; ++i)
          if (g[i] > g[k]) k = i;
        const int o1 = (k + 1) % 3, o2 = (k + 2) % 3;
        const int m = g[o1] < g[o2] ? o1 : o2;
        const int expect = 2 * k + (m == o1 ? 0 : 1);
        EXPECT_EQ(SnyderProjection::sub_triangle(g[0], g[1], g[2]), expect) << a << b << c;
      }
}

}  // namespace ICOBRDF_UNITY_ID
