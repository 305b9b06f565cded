// Height map, eLabrador eq. (10): the highest occupied voxel of each pillar, below eye level.
#include <gtest/gtest.h>

#include <cmath>

#include "navaid/core/errors.hpp"
#include "navaid/mapping/height_map.hpp"
#include "test_support.hpp"

namespace navaid::mapping {
namespace {

MapVoxel voxel(double x, double y, double z, double occupancy, double size = 0.1) {
  MapVoxel v;
  v.center_W = Vec3(x, y, z);
  v.size_m = size;
  v.occupancy = occupancy;
  return v;
}

TEST(HeightMap, HighestOccupiedVoxelOfEachPillar) {
  const GridGeometry g(Cell2(0, 0), 4, 4, 0.1);
  const double camera = 1.5;
  const MapVoxels voxels{
      voxel(0.15, 0.15, 0.05, 0.9),  // cell (1, 1): floor
      voxel(0.15, 0.15, 0.55, 0.8),  //   a box top: H = 0.55
      voxel(0.15, 0.15, 1.20, 0.3),  //   free (p < 0.5): not occupied
      voxel(0.15, 0.15, 1.70, 0.9),  //   above the camera: not part of the map
      voxel(0.25, 0.15, 0.05, 0.5),  // cell (2, 1): p exactly at the threshold counts
      voxel(0.05, 0.35, 1.50, 0.7),  // cell (0, 3): exactly at camera height counts
  };
  const HeightMap h = build_height_map(voxels, g, camera, HeightMapConfig{});
  EXPECT_FLOAT_EQ(h.at(1, 1), 0.55F);
  EXPECT_FLOAT_EQ(h.at(2, 1), 0.05F);
  EXPECT_FLOAT_EQ(h.at(0, 3), 1.5F);
  int known = 0;
  for (const float v : h.cells().pixels) known += HeightMap::is_known(v) ? 1 : 0;
  EXPECT_EQ(known, 3);
  EXPECT_FALSE(HeightMap::is_known(h.at(3, 3)));
  EXPECT_FLOAT_EQ(*h.value_at(Vec2(0.12, 0.19)), 0.55F);
  EXPECT_FALSE(h.value_at(Vec2(-0.01, 0.1)).has_value());

  // Raising the cut-off lets the 1.7 m voxel in.
  HeightMapConfig high;
  high.max_above_camera_m = 0.5;
  EXPECT_FLOAT_EQ(build_height_map(voxels, g, camera, high).at(1, 1), 1.7F);
}

TEST(HeightMap, LargeVoxelsCoverEveryCellOfTheirFootprint) {
  const GridGeometry g(Cell2(0, 0), 4, 4, 0.1);
  const HeightMap h = build_height_map({voxel(0.2, 0.2, 0.3, 0.9, 0.2)}, g, 1.5, HeightMapConfig{});
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 4; ++x) {
      const bool inside = x >= 1 && x <= 2 && y >= 1 && y <= 2;
      EXPECT_EQ(HeightMap::is_known(h.at(x, y)), inside) << x << "," << y;
    }
  }
}

TEST(HeightMap, ConfigKeysAndRanges) {
  const HeightMapConfig c = read_height_map_config(
      Config::parse("mapping: {height: {occupied_threshold: 0.7, max_above_camera_m: 0.3}}"));
  EXPECT_DOUBLE_EQ(c.occupied_threshold, 0.7);
  EXPECT_DOUBLE_EQ(c.max_above_camera_m, 0.3);
  const std::string msg = testing::error_message<ConfigError>(
      [] { read_height_map_config(Config::parse("mapping: {height: {occupied_threshold: 0}}", "h.yaml")); });
  EXPECT_NE(msg.find("mapping.height.occupied_threshold"), std::string::npos) << msg;
  EXPECT_NE(msg.find("h.yaml"), std::string::npos) << msg;
}

}  // namespace
}  // namespace navaid::mapping
