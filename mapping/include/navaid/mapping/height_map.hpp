#pragma once
// Height map, eLabrador eq. (10): H(g) = argmax_h {h : M3D(g, h) = 1}, the height of the highest
// occupied voxel of the pillar over cell g. Voxels far above the user (ceilings, tree canopies) are
// left out: they are no step the user meets, and with them every indoor cell would read "ceiling".
#include "navaid/core/config.hpp"
#include "navaid/mapping/grid_layer.hpp"
#include "navaid/mapping/map_voxel.hpp"

namespace navaid::mapping {

struct HeightMapConfig {
  /// A voxel is occupied (M3D = 1) at p >= this (OctoMap's default occupancy threshold).
  double occupied_threshold = 0.5;
  /// Voxels whose centre lies higher than camera height + this are not part of the height map [m]:
  /// 0 keeps everything up to eye level (what the user can walk into or over).
  double max_above_camera_m = 0.0;
};

/// Keys mapping.height.occupied_threshold in [0.01, 1] and mapping.height.max_above_camera_m in
/// [-2, 5].
HeightMapConfig read_height_map_config(const Config& config);

/// Cell value: centre height in W [m] of the pillar's highest occupied voxel; NaN where the pillar
/// holds no occupied voxel (unknown or open ground not seen).
class HeightMap : public GridLayer<float> {
 public:
  explicit HeightMap(const GridGeometry& geometry);
  static bool is_known(float h);
};

/// Builds H(g) from the voxels; `camera_height_W` is the camera centre's z in W [m].
HeightMap build_height_map(const MapVoxels& voxels, const GridGeometry& geometry, double camera_height_W,
                           const HeightMapConfig& config);

}  // namespace navaid::mapping
