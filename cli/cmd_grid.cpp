// icobrdf grid: build the hemi-icosahedral tessellation and print its cell statistics; optionally export
// the mesh as Wavefront OBJ.
//   icobrdf grid --level L [--geodesic] [--json] [--export-obj FILE.obj]
#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <iostream>
#include <memory>

#include "cli/commands.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/grid_obj_file.hpp"
#include "icobrdf/io/grid_summary.hpp"
#include "icobrdf/mesh/tessellation.hpp"

namespace icobrdf::cli {
namespace {

struct GridOptions {
  int level = -1;
  bool geodesic = false;
  bool json = false;
  std::string obj;
};

void run_grid(const GridOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  const Grid g = o.geodesic ? build_geodesic_grid(o.level) : build_equal_area_grid(o.level);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  nlohmann::json j = grid_summary_json(g);
  j["seconds"] = seconds;
  if (!o.obj.empty()) {
    write_grid_obj_file(g, o.obj);
    j["obj"] = o.obj;
  }
  if (o.json) {
    std::cout << j.dump(2) << "\n";
    return;
  }
  std::cout << fmt::format("{} grid, level {}: {} cells ({} whole, {} half), {} vertices\n", to_string(g.kind), g.level, g.cells(),
                           j["whole_cells"].get<int>(), j["half_cells"].get<int>(), g.vertices.rows())
            << fmt::format("solid angle [sr]: min {:.17g}, max {:.17g}, sum {:.17g} (2 pi = {:.17g})\n",
                           j["solid_angle_min"].get<double>(), j["solid_angle_max"].get<double>(),
                           j["solid_angle_sum"].get<double>(), 2 * M_PI)
            << fmt::format("whole cells max/min: {:.15g}\n", j["whole_cell_ratio"].get<double>())
            << fmt::format("cubature: degree {}, {} points\n", g.cubature_degree, g.cubature_points.rows())
            << fmt::format("build time: {:.3f} s\n", seconds);
  if (!o.obj.empty()) std::cout << fmt::format("mesh written to {}\n", o.obj);
}

void add_grid_command(CLI::App& app) {
  auto opts = std::make_shared<GridOptions>();
  auto* cmd = app.add_subcommand("grid", "Build the hemi-icosahedral tessellation and report its cells");
  cmd->add_option("--level", opts->level, "Subdivision level L (0..8): 10*4^L + 2^(L+1) cells")->required()->check(CLI::Range(0, 8));
  cmd->add_flag("--geodesic", opts->geodesic, "Geodesic (gnomonic) baseline instead of the equal-area grid");
  cmd->add_flag("--json", opts->json, "Machine-readable output");
  cmd->add_option("--export-obj", opts->obj, "Write the mesh as Wavefront OBJ to this file");
  cmd->callback([opts] { run_grid(*opts); });
}

const CommandRegistrar kCmdGridRegistrar("grid", add_grid_command);

}  // namespace
}  // namespace icobrdf::cli
