// A minimal path-tracing loop over a renderer-facing material (icobrdf/io/render_material.hpp), with a Monte
// Carlo white-furnace check: a plane of the material under a uniform white sky (radiance 1 from every
// direction above it). The radiance it sends towards a viewer at w is the directional albedo a(w) (reciprocity),
// which the loop estimates from per-sample draws (float path) and which is checked against an independent
// Gauss-Legendre quadrature of f cos (plus the delta parts' weights) within 3 standard errors.
//   path_trace_furnace [SOURCE [PATHS]]      defaults: model:0.4*lambert+0.4*ggx:alpha=0.2+0.2*mirror, 200000
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/grid/gauss_legendre.hpp"
#include "icobrdf/io/render_material.hpp"

namespace {

using namespace icobrdf;

// a(w) = integral of f(w, w_r) cos(theta_r) dw_r + delta weights, by 96 x 192 Gauss-Legendre nodes.
double albedo_by_quadrature(const RenderMaterial& m, const Eigen::Vector3d& w) {
  const QuadratureRule gz = gauss_legendre(96, 0.0, 1.0), gp = gauss_legendre(192, -M_PI, M_PI);
  double s = 0.0;
  for (Eigen::Index a = 0; a < gz.nodes.size(); ++a)
    for (Eigen::Index b = 0; b < gp.nodes.size(); ++b) {
      const double z = gz.nodes[a], st = std::sqrt(std::max(0.0, 1.0 - z * z));
      const Eigen::Vector3d wr(st * std::cos(gp.nodes[b]), st * std::sin(gp.nodes[b]), z);
      s += gz.weights[a] * gp.weights[b] * m.eval(w, wr)[0] * z;
    }
  return s + m.delta_albedo();
}

}  // namespace

int main(int argc, char** argv) {
  const std::string source = argc > 1 ? argv[1] : "model:0.4*lambert+0.4*ggx:alpha=0.2+0.2*mirror";
  RenderMaterialOptions options;  // 12 incident nodes, 64 x 64 half-vector cells: enough for these smooth materials
  options.table.theta_nodes = 12;
  options.table.t_bins = 64;
  options.table.phi_bins = 64;
  const RenderMaterial material = RenderMaterial::open(source, options);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  const int kPaths = argc > 2 ? std::stoi(argv[2]) : 200000;
  constexpr int kMaxDepth = 8;
  bool ok = true;
  for (const double view_deg : {0.0, 40.0, 70.0}) {
    const Eigen::Vector3f view = direction_from_angles(view_deg * M_PI / 180, 0.5).cast<float>();
    double sum = 0.0, sum2 = 0.0;
    for (int p = 0; p < kPaths; ++p) {
      // The camera ray hits the plane; from there the path continues along sampled directions.
      float throughput = 1.0f, radiance = 0.0f;
      Eigen::Vector3f wo = view;
      for (int depth = 0; depth < kMaxDepth; ++depth) {
        const MaterialSample<float> s = material.sample(wo, uniform(rng), uniform(rng));
        if (!s.valid()) break;  // absorbed (a draw below the horizon)
        throughput *= s.weight[0];
        // Nothing else is in the scene: the sampled ray leaves for the sky, which sends radiance 1.
        radiance += throughput * 1.0f;
        break;
      }
      sum += radiance, sum2 += static_cast<double>(radiance) * radiance;
    }
    const double mean = sum / kPaths, se = std::sqrt(std::max(0.0, sum2 / kPaths - mean * mean) / kPaths);
    const double expected = albedo_by_quadrature(material, view.cast<double>());
    const bool pass = std::abs(mean - expected) <= 3.0 * se;
    ok &= pass;
    std::printf("view %4.1f deg: furnace radiance %.5f +- %.5f (1 s.e.), directional albedo by quadrature %.5f: %s\n", view_deg, mean,
                se, expected, pass ? "within 3 s.e." : "MISMATCH");
  }
  std::printf("%s: %s\n", source.c_str(), ok ? "white furnace matches" : "white furnace MISMATCH");
  return ok ? 0 : 1;
}
