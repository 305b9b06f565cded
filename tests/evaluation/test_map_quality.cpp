// Map quality against a known world: precision, recall, semantic accuracy, deliberate obstacles.
#include <gtest/gtest.h>

#include "navaid/evaluation/map_quality.hpp"

namespace navaid::evaluation {
namespace {

using C = SemanticClass;

/// A floor and one box obstacle 2 m ahead (the deliberate obstacle), nothing else.
simulation::Scenario box_world() {
  simulation::Scenario s;
  s.name = "box";
  s.ground_z_m = 0.0;
  s.world.add(simulation::PlanePatch{SE3(Quat::Identity(), Vec3(0, 0, 0)), 6.0, 6.0}, {C::kFloor});
  const auto box = s.world.add(simulation::Box{SE3(Quat::Identity(), Vec3(2.0, 0.0, 0.5)), Vec3(0.2, 0.2, 0.5)},
                               {C::kChair});
  s.deliberate_obstacles = {box};
  s.path = {simulation::Vec2(0, 0), simulation::Vec2(1, 0)};
  return s;
}

/// Points on the box's -x face (what a camera at the origin sees) from height z0, of class `semantic`.
mapping::SemanticPointCloud face_cloud(double x, C semantic, double z0 = 0.02) {
  mapping::SemanticPointCloud cloud;
  cloud.origin_W = Vec3(0, 0, 1.0);
  cloud.labelled = true;
  for (double y = -0.18; y <= 0.18; y += 0.02)
    for (double z = z0; z <= 0.98; z += 0.02)
      cloud.points.push_back({Eigen::Vector3f(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)),
                              {semantic, 0.9f}});
  return cloud;
}

mapping::SemanticMap map_with(const mapping::SemanticPointCloud& cloud) {
  mapping::SemanticMapConfig c;
  c.resolution_m = 0.1;
  mapping::SemanticMap map(c);
  map.set_window_center(Vec3(0, 0, 1.0));
  map.insert(cloud);
  return map;
}

TEST(MapQuality, AMapOfTheTruthIsPreciseAndFindsTheObstacle) {
  const auto scenario = box_world();
  MapQualityAccumulator acc(scenario, 0.1);
  acc.add_snapshot(map_with(face_cloud(1.801, C::kChair)), Vec3(0, 0, 1.0));
  const MapQuality q = acc.result();
  EXPECT_EQ(q.snapshots, 1u);
  EXPECT_GT(q.true_positive, 0u);
  EXPECT_EQ(q.false_positive, 0u);
  EXPECT_DOUBLE_EQ(q.precision, 1.0);
  // The face's voxels were observed and detected; the floor under the rays was not hit (the rays
  // end on the face), so it is observed free space or unknown, never a detection.
  EXPECT_GT(q.recall, 0.0);
  ASSERT_EQ(q.deliberate.size(), 1u);
  EXPECT_TRUE(q.deliberate[0].in_reach);
  EXPECT_TRUE(q.deliberate[0].detected);
  EXPECT_DOUBLE_EQ(q.deliberate_recall, 1.0);
  EXPECT_DOUBLE_EQ(q.semantic_accuracy, 1.0);
  EXPECT_EQ(q.per_class.at(C::kChair).correct, q.per_class.at(C::kChair).total);
}

TEST(MapQuality, AGhostWallIsAFalsePositiveAndTheObstacleIsMissed) {
  const auto scenario = box_world();
  MapQualityAccumulator acc(scenario, 0.1);
  // 0.6 m in front of the box, and clear of the floor by more than the one-voxel tolerance.
  acc.add_snapshot(map_with(face_cloud(1.2, C::kWall, 0.22)), Vec3(0, 0, 1.0));
  const MapQuality q = acc.result();
  EXPECT_EQ(q.true_positive, 0u);
  EXPECT_GT(q.false_positive, 0u);
  EXPECT_DOUBLE_EQ(q.precision, 0.0);
  EXPECT_TRUE(q.deliberate[0].in_reach);
  EXPECT_FALSE(q.deliberate[0].detected);
  EXPECT_DOUBLE_EQ(q.deliberate_recall, 0.0);
}

TEST(MapQuality, WrongClassLowersSemanticAccuracyOnly) {
  const auto scenario = box_world();
  MapQualityAccumulator acc(scenario, 0.1);
  acc.add_snapshot(map_with(face_cloud(1.801, C::kTable)), Vec3(0, 0, 1.0));
  const MapQuality q = acc.result();
  EXPECT_DOUBLE_EQ(q.precision, 1.0);
  EXPECT_DOUBLE_EQ(q.semantic_accuracy, 0.0);
  EXPECT_EQ(q.per_class.at(C::kChair).correct, 0u);
}

TEST(MapQuality, ObstaclesFarFromTheUserAreNotInReach) {
  const auto scenario = box_world();
  MapQualityAccumulator acc(scenario, 0.1);
  mapping::SemanticMap empty = map_with({});
  acc.add_snapshot(empty, Vec3(-20, 0, 1.0));
  EXPECT_FALSE(acc.result().deliberate[0].in_reach);
  EXPECT_DOUBLE_EQ(acc.result().deliberate_recall, 0.0);
}

}  // namespace
}  // namespace navaid::evaluation
