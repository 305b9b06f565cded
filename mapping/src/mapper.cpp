#include "navaid/mapping/mapper.hpp"

#include "navaid/mapping/config_schema.hpp"

#include <chrono>

namespace navaid::mapping {

namespace {
const ConfigKey<bool> kLayers{"mapping.layers", MapperConfig{}.layers,
                              "build the 2D layers and the 2D ESDF after every mapped frame (what planners read)"};
}  // namespace

ConfigSchema mapper_config_schema() {
  return ConfigSchema()
      .add(semantic_point_cloud_config_schema())
      .add(semantic_map_config_schema())
      .add(mapping_gate_config_schema())
      .add(kLayers)
      .add(grid_config_schema())
      .add(height_map_config_schema())
      .add(undulation_config_schema())
      .add(collision_config_schema())
      .add(cost_map_config_schema())
      .add(esdf_2d_config_schema());
}

ConfigSchema config_schema() {
  return mapper_config_schema()
      .add(esdf_3d_config_schema())
      .add(obstacle_pipeline_config_schema())
      .add(segmentation_link_config_schema());
}

MapperConfig read_mapper_config(const Config& c) {
  MapperConfig m;
  m.cloud = read_semantic_point_cloud_config(c);
  m.map = read_semantic_map_config(c);
  m.gate = read_mapping_gate_config(c);
  m.layers = get(c, kLayers);
  m.grid = read_grid_config(c);
  m.height = read_height_map_config(c);
  m.undulation = read_undulation_config(c);
  m.collision = read_collision_config(c);
  m.cost = read_cost_map_config(c);
  m.esdf = read_esdf_2d_config(c);
  return m;
}

namespace {
double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

Mapper::Mapper(const MapperConfig& config, const CameraCalibration& camera)
    : config_(config), camera_(camera), map_(config.map) {}

MapperFrameResult Mapper::process(const RgbdFrame& frame, const StateEstimate& estimate) {
  MapperFrameResult r;
  ++counters_.frames;
  r.uncertainty = pose_uncertainty(estimate);
  r.gated = r.uncertainty;
  if (config_.gate.scope == UncertaintyScope::kWindow &&
      estimate.mode != EstimatorMode::kInitializing && estimate.mode != EstimatorMode::kLost)
    r.gated = uncertainty_window_.add(estimate.t, r.uncertainty, config_.gate.window_s);
  last_uncertainty_ = r.gated;
  switch (gate(estimate, r.gated, config_.gate)) {
    case GateDecision::kSkipMode:
      r.outcome = FrameOutcome::kNotLocalised;
      ++counters_.not_localised;
      return r;
    case GateDecision::kSkipUncertain:
      r.outcome = FrameOutcome::kTooUncertain;
      ++counters_.too_uncertain;
      return r;
    case GateDecision::kMap:
      break;
  }
  if (frame.depth.empty()) {
    r.outcome = FrameOutcome::kNoDepth;
    ++counters_.no_depth;
    return r;
  }
  auto t0 = std::chrono::steady_clock::now();
  const SemanticPointCloud cloud = make_semantic_point_cloud(frame, camera_, estimate.T_W_B, config_.cloud);
  r.cloud_ms = ms_since(t0);
  t0 = std::chrono::steady_clock::now();
  map_.set_window_center(estimate.T_W_B.t);
  r.insert = map_.insert(cloud);
  r.insert_ms = ms_since(t0);
  r.points = cloud.points.size();
  counters_.points += r.points;
  ++counters_.mapped;
  if (config_.layers) {
    t0 = std::chrono::steady_clock::now();
    const MapVoxels voxels = map_.occupied_voxels();
    const GridGeometry grid = GridGeometry::around(estimate.T_W_B.t.head<2>(), config_.grid);
    const double camera_z = cloud.origin_W.z();
    HeightMap height = build_height_map(voxels, grid, camera_z, config_.height);
    UndulationMap undulation = build_undulation_map(height, config_.undulation);
    CollisionMap collision = build_collision_map(voxels, grid, camera_z, config_.collision);
    CostMap cost = build_cost_map(collision, undulation, r.gated.sigma_xy, config_.cost);
    r.layers_ms = ms_since(t0);
    t0 = std::chrono::steady_clock::now();
    Esdf2d esdf(config_.esdf);
    esdf.update(cost);
    r.esdf_ms = ms_since(t0);
    local_maps_.emplace(LocalMaps{std::move(height), std::move(undulation), std::move(collision), std::move(cost),
                                  std::move(esdf)});
  }
  return r;
}

}  // namespace navaid::mapping
