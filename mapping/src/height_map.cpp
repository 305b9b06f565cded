#include "navaid/mapping/height_map.hpp"

#include <cmath>
#include <limits>

namespace navaid::mapping {

HeightMapConfig read_height_map_config(const Config& config) {
  HeightMapConfig h;
  h.occupied_threshold = config.get_double("mapping.height.occupied_threshold", h.occupied_threshold, {0.01, 1.0});
  h.max_above_camera_m = config.get_double("mapping.height.max_above_camera_m", h.max_above_camera_m, {-2.0, 5.0});
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
