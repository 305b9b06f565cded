#include "navaid/mapping/height_map.hpp"

#include "navaid/mapping/config_schema.hpp"

#include <cmath>
#include <limits>

namespace navaid::mapping {

namespace {
const ConfigKey<double> kHeightMapOccupiedThreshold{"mapping.height.occupied_threshold", HeightMapConfig{}.occupied_threshold,
                                           {0.01, 1.0}, "a voxel is occupied at or above this probability"};
const ConfigKey<double> kMaxAboveCamera{"mapping.height.max_above_camera_m", HeightMapConfig{}.max_above_camera_m,
                                        {-2.0, 5.0}, "voxels higher than the camera plus this are left out [m]"};
}  // namespace

ConfigSchema height_map_config_schema() { return ConfigSchema().add(kHeightMapOccupiedThreshold).add(kMaxAboveCamera); }

HeightMapConfig read_height_map_config(const Config& config) {
  HeightMapConfig h;
  h.occupied_threshold = get(config, kHeightMapOccupiedThreshold);
  h.max_above_camera_m = get(config, kMaxAboveCamera);
  return h;
}

HeightMap::HeightMap(const GridGeometry& geometry)
    : GridLayer<float>(geometry, std::numeric_limits<float>::quiet_NaN()) {}

bool HeightMap::is_known(float h) { return !std::isnan(h); }

HeightMap build_height_map(const MapVoxels& voxels, const GridGeometry& geometry, double camera_height_W,
                           const HeightMapConfig& config) {
  HeightMap map(geometry);
  const double top = camera_height_W + config.max_above_camera_m;
  for (const MapVoxel& v : voxels) {
    if (v.occupancy < config.occupied_threshold || v.center_W.z() > top) continue;
    const auto h = static_cast<float>(v.center_W.z());
    for_each_footprint_cell(geometry, v.center_W, v.size_m, [&](const Cell2& c) {
      float& cell = map.at(c);
      // NaN compares false: the first voxel of a pillar always lands.
      if (!(cell >= h)) cell = h;
    });
  }
  return map;
}

}  // namespace navaid::mapping
