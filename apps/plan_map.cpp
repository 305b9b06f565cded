#include "plan_map.hpp"

#include <fmt/format.h>
#include <octomap/OcTree.h>

#include "command_schemas.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/experiments/scenario_cost_map.hpp"
#include "navaid/io/occupancy_map_file.hpp"
#include "navaid/mapping/collision_map.hpp"
#include "navaid/mapping/height_map.hpp"
#include "navaid/mapping/octomap_voxels.hpp"
#include "navaid/mapping/semantic_map.hpp"
#include "navaid/mapping/undulation_map.hpp"
#include "navaid/planning/occupancy_cost_map.hpp"

namespace navaid::cli {

namespace {

using mapping::Vec2;

PlanMap from_scenario(const std::string& name, const Config& config) {
  experiments::ScenarioCostMap m = experiments::scenario_cost_map(name, config);
  return PlanMap{std::move(m.cost), std::move(m.description)};
}

PlanMap from_map_server(const std::filesystem::path& yaml, const Config& config) {
  const io::OccupancyMapFile file = io::read_occupancy_map(yaml);
  if (file.origin_yaw_rad != 0.0) throw ConfigError(yaml.string(), "origin", "rotated maps (yaw != 0) are not supported");
  Vec2 snap = Vec2::Zero();
  mapping::CostMap cost = planning::cost_map_from_occupancy(
      file.image.width, file.image.height, file.resolution_m, Vec2(file.origin_x_m, file.origin_y_m),
      [&](int x, int y) {
        switch (file.cell(x, y)) {
          case io::OccupancyCell::kFree: return planning::OccupancyValue::kFree;
          case io::OccupancyCell::kOccupied: return planning::OccupancyValue::kOccupied;
          case io::OccupancyCell::kUnknown: break;
        }
        return planning::OccupancyValue::kUnknown;
      },
      planning::read_occupancy_cost_config(config), &snap);
  return PlanMap{std::move(cost), fmt::format("map_server map {} ({} x {} px of {} m; origin snapped by {:.3f} m)",
                                              yaml.string(), file.image.width, file.image.height, file.resolution_m,
                                              snap.norm())};
}

PlanMap from_voxels(const mapping::MapVoxels& voxels, double resolution, const std::string& what, const Config& config) {
  if (voxels.empty()) throw IoError(what, "the map holds no occupied voxel");
  Vec3 lo = voxels.front().center_W;
  Vec3 hi = lo;
  for (const mapping::MapVoxel& v : voxels) {
    lo = lo.cwiseMin(v.center_W);
    hi = hi.cwiseMax(v.center_W);
  }
  const mapping::Cell2 lo_cell((lo.head<2>() / resolution).array().floor().cast<int>());
  const mapping::Cell2 hi_cell((hi.head<2>() / resolution).array().floor().cast<int>());
  const mapping::GridGeometry g(lo_cell, hi_cell.x() - lo_cell.x() + 1, hi_cell.y() - lo_cell.y() + 1, resolution);
  const double camera_z = get(config, octomap_camera_height_key());
  const mapping::HeightMap height = mapping::build_height_map(voxels, g, camera_z, mapping::read_height_map_config(config));
  const mapping::UndulationMap undulation = mapping::build_undulation_map(height, mapping::read_undulation_config(config));
  const mapping::CollisionMap collision =
      mapping::build_collision_map(voxels, g, camera_z, mapping::read_collision_config(config));
  mapping::CostMap cost = mapping::build_cost_map(collision, undulation, 0.0, mapping::read_cost_map_config(config));
  return PlanMap{std::move(cost), fmt::format("{} ({} occupied voxels; cost map eq. 8 of {} x {} cells of {} m, camera "
                                              "at z = {:.2f} m)",
                                              what, voxels.size(), g.width(), g.height(), resolution, camera_z)};
}

PlanMap from_octomap(const std::filesystem::path& file, const Config& config) {
  const std::string ext = file.extension().string();
  if (ext == ".ot") {
    // navaid's semantic map first (it knows classes); a plain OcTree otherwise.
    std::string semantic_error;
    try {
      // The whole saved map, not a window around the origin.
      mapping::SemanticMapConfig whole = mapping::read_semantic_map_config(config);
      whole.window_size_m = 1e6;
      whole.window_below_m = whole.window_above_m = 1e6;
      const mapping::SemanticMap map = mapping::SemanticMap::load(file, whole);
      return from_voxels(map.occupied_voxels(), map.config().resolution_m, "semantic map " + file.string(), config);
    } catch (const IoError& e) {
      semantic_error = e.what();
    }
    std::unique_ptr<octomap::AbstractOcTree> tree(octomap::AbstractOcTree::read(file.string()));
    auto* occupancy = dynamic_cast<octomap::OcTree*>(tree.get());
    if (occupancy == nullptr) {
      throw IoError(file.string(), "neither a navaid semantic map (" + semantic_error + ") nor an OctoMap OcTree");
    }
    double x0, y0, z0, x1, y1, z1;
    occupancy->getMetricMin(x0, y0, z0);
    occupancy->getMetricMax(x1, y1, z1);
    return from_voxels(mapping::octomap_to_voxels(*occupancy, Vec3(x0, y0, z0), Vec3(x1, y1, z1)),
                       occupancy->getResolution(), "OctoMap " + file.string(), config);
  }
  octomap::OcTree tree(0.1);
  if (!std::filesystem::is_regular_file(file) || !tree.readBinary(file.string())) {
    throw IoError(file.string(), "cannot read as an OctoMap binary tree (.bt)");
  }
  double x0, y0, z0, x1, y1, z1;
  tree.getMetricMin(x0, y0, z0);
  tree.getMetricMax(x1, y1, z1);
  return from_voxels(mapping::octomap_to_voxels(tree, Vec3(x0, y0, z0), Vec3(x1, y1, z1)), tree.getResolution(),
                     "OctoMap " + file.string(), config);
}

}  // namespace

PlanMap load_plan_map(const std::string& spec, const Config& config) {
  if (spec.rfind("scenario:", 0) == 0) return from_scenario(spec.substr(9), config);
  const std::filesystem::path path(spec);
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    if (std::filesystem::is_regular_file(path / "map.ot")) return from_octomap(path / "map.ot", config);
    std::vector<std::filesystem::path> yamls;
    for (const auto& entry : std::filesystem::directory_iterator(path)) {
      if (entry.path().extension() == ".yaml" && entry.path().filename() != "config.yaml") yamls.push_back(entry.path());
    }
    if (yamls.size() != 1) {
      throw UsageError(fmt::format("--map {}: a folder must hold map.ot or exactly one map_server .yaml (found {})",
                                   spec, yamls.size()));
    }
    return from_map_server(yamls.front(), config);
  }
  if (!std::filesystem::exists(path, ec)) throw IoError(spec, "map does not exist");
  const std::string ext = path.extension().string();
  if (ext == ".yaml" || ext == ".yml") return from_map_server(path, config);
  if (ext == ".bt" || ext == ".ot") return from_octomap(path, config);
  throw UsageError(fmt::format("--map {}: unknown kind (scenario:NAME, .yaml, .bt, .ot, or a folder)", spec));
}

}  // namespace navaid::cli
