// Collision map, eLabrador eq. (9), with navaid's Table II and the geometric rule p(m).
#include <gtest/gtest.h>

#include <cmath>

#include "navaid/core/errors.hpp"
#include "navaid/mapping/collision_map.hpp"
#include "test_support.hpp"

namespace navaid::mapping {
namespace {

MapVoxel voxel(double x, double y, double z, double occupancy, SemanticClass c) {
  MapVoxel v;
  v.center_W = Vec3(x, y, z);
  v.size_m = 0.1;
  v.occupancy = occupancy;
  v.semantic = c;
  v.class_probability = 0.9;
  return v;
}

double ps(SemanticClass c) { return default_semantic_collision_table()[static_cast<std::size_t>(c)]; }

TEST(CollisionMap, EquationNineOnHandComputedPillars) {
  const GridGeometry g(Cell2(0, 0), 4, 1, 0.1);
  const double camera = 1.5;
  using S = SemanticClass;
  const MapVoxels voxels{
      // Cell 0: sidewalk (p(s) 0, m -1.45 in band), person (1, in band), pole above the camera
      // (m +0.5: p(m) 0). p = (0 * 0.9 + 1 * 0.8 + 0 * 0.6) / (0.9 + 0.8 + 0.6).
      voxel(0.05, 0.05, 0.05, 0.9, S::kSidewalk),
      voxel(0.05, 0.05, 1.00, 0.8, S::kPerson),
      voxel(0.05, 0.05, 2.00, 0.6, S::kPole),
      // Cell 1: vegetation (0.8) and road (0.8), both in band: (0.8 * 1 + 0.8 * 0.5) / 1.5.
      voxel(0.15, 0.05, 1.00, 1.0, S::kVegetation),
      voxel(0.15, 0.05, 0.00, 0.5, S::kRoad),
      // Cell 2: only a free voxel (p < 0.5): unknown.
      voxel(0.25, 0.05, 1.00, 0.3, S::kCar),
      // Cell 3: a geometry-only voxel below the band (m = -2.1): occupied but harmless.
      voxel(0.35, 0.05, -0.60, 0.95, S::kUnlabeled),
  };
  const CollisionMap m = build_collision_map(voxels, g, camera, CollisionConfig{});
  EXPECT_NEAR(m.at(0, 0), (ps(S::kPerson) * 0.8) / 2.3, 1e-6);
  EXPECT_NEAR(m.at(0, 0), 0.8 / 2.3, 1e-6);
  EXPECT_NEAR(m.at(1, 0), (0.8 * 1.0 + 0.8 * 0.5) / 1.5, 1e-6);
  EXPECT_FALSE(CollisionMap::is_known(m.at(2, 0)));
  EXPECT_FLOAT_EQ(m.at(3, 0), 0.0F);
}

TEST(CollisionMap, GeometricRuleEdges) {
  const CollisionConfig c;
  EXPECT_EQ(geometric_collision_probability(-2.0, c), 1.0);
  EXPECT_EQ(geometric_collision_probability(0.0, c), 1.0);
  EXPECT_EQ(geometric_collision_probability(-1.0, c), 1.0);
  EXPECT_EQ(geometric_collision_probability(-2.0 - 1e-9, c), 0.0);
  EXPECT_EQ(geometric_collision_probability(1e-9, c), 0.0);
  // Through the map: camera at 2 m, voxels at m = -2 and m = 0 exactly, and just outside.
  const GridGeometry g(Cell2(0, 0), 4, 1, 0.1);
  const MapVoxels voxels{
      voxel(0.05, 0.05, 0.0, 1.0, SemanticClass::kWall),   // m = -2
      voxel(0.15, 0.05, 2.0, 1.0, SemanticClass::kWall),   // m = 0
      voxel(0.25, 0.05, -0.001, 1.0, SemanticClass::kWall),  // m = -2.001
      voxel(0.35, 0.05, 2.001, 1.0, SemanticClass::kWall),   // m = +0.001
  };
  const CollisionMap m = build_collision_map(voxels, g, 2.0, CollisionConfig{});
  EXPECT_FLOAT_EQ(m.at(0, 0), 1.0F);
  EXPECT_FLOAT_EQ(m.at(1, 0), 1.0F);
  EXPECT_FLOAT_EQ(m.at(2, 0), 0.0F);
  EXPECT_FLOAT_EQ(m.at(3, 0), 0.0F);
}

TEST(CollisionMap, DefaultTableTwo) {
  using S = SemanticClass;
  for (const S walkable : {S::kSidewalk, S::kCrosswalk, S::kFloor, S::kTactilePaving}) EXPECT_EQ(ps(walkable), 0.0);
  for (const S solid : {S::kCar, S::kPerson, S::kPole, S::kWall, S::kBuilding, S::kUnlabeled}) EXPECT_EQ(ps(solid), 1.0);
  EXPECT_GT(ps(S::kRoad), 0.5);
  for (const double p : default_semantic_collision_table()) {
    EXPECT_GE(p, 0.0);
    EXPECT_LE(p, 1.0);
  }
}

TEST(CollisionMap, TableLookupByClassName) {
  const CollisionConfig c = read_collision_config(Config::parse(R"(
mapping:
  collision:
    occupied_threshold: 0.6
    min_relative_height_m: -1.3
    semantic_probability:
      road: 0.3
      tree-trunk: 0.9
)"));
  EXPECT_DOUBLE_EQ(c.occupied_threshold, 0.6);
  EXPECT_DOUBLE_EQ(c.min_relative_height_m, -1.3);
  EXPECT_DOUBLE_EQ(c.max_relative_height_m, 0.0);
  EXPECT_DOUBLE_EQ(c.semantic_probability[static_cast<std::size_t>(SemanticClass::kRoad)], 0.3);
  EXPECT_DOUBLE_EQ(c.semantic_probability[static_cast<std::size_t>(SemanticClass::kTreeTrunk)], 0.9);
  EXPECT_DOUBLE_EQ(c.semantic_probability[static_cast<std::size_t>(SemanticClass::kSidewalk)], 0.0);
}

TEST(CollisionMap, UnknownClassNameNamesTheKey) {
  const auto e = testing::expect_throw<ConfigError>([] {
    read_collision_config(Config::parse("mapping: {collision: {semantic_probability: {lamppost: 1}}}", "c.yaml"));
  });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->key(), "mapping.collision.semantic_probability.lamppost");
  EXPECT_EQ(e->file(), "c.yaml");
  EXPECT_NE(std::string(e->what()).find("tree-trunk"), std::string::npos) << e->what();  // lists the known names
}

TEST(CollisionMap, ConfigRanges) {
  const std::string out_of_range = testing::error_message<ConfigError>(
      [] { read_collision_config(Config::parse("mapping: {collision: {semantic_probability: {car: 1.5}}}")); });
  EXPECT_NE(out_of_range.find("mapping.collision.semantic_probability.car"), std::string::npos) << out_of_range;
  const std::string inverted = testing::error_message<ConfigError>([] {
    read_collision_config(
        Config::parse("mapping: {collision: {min_relative_height_m: 0.5, max_relative_height_m: 0.2}}"));
  });
  EXPECT_NE(inverted.find("mapping.collision.min_relative_height_m"), std::string::npos) << inverted;
}

}  // namespace
}  // namespace navaid::mapping
