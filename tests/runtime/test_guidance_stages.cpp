// The four guidance chains as the device builds them: each from the configuration, the camera and
// the mission alone (no recording, no ground truth), with a clear error when the mission lacks
// what the chain needs, and the chain's first answers on known input.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "device_fixture.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/planning/osm_foot_graph.hpp"
#include "navaid/runtime/guidance_stage.hpp"
#include "navaid/simulation/osm_export.hpp"
#include "navaid/simulation/scenario.hpp"
#include "test_support.hpp"

namespace navaid::runtime {
namespace {

Config preset(const std::string& name, const std::vector<std::string>& overrides = {}) {
  return Config::load(device_preset_file(name), overrides);
}

std::unique_ptr<GuidanceStage> stage_for(const Config& config, const CameraCalibration& camera,
                                         const DeviceMission& mission) {
  const DeviceSpec spec = read_device_spec(config);
  return make_guidance_stage({spec, config, camera, mission});
}

StateEstimate localised_at(Timestamp t) {
  StateEstimate e;
  e.t = t;
  e.T_W_B = SE3(Quat::Identity(), Vec3(0, 0, 0.8));
  e.covariance = 1e-6 * Mat15::Identity();
  e.mode = EstimatorMode::kRgbdVio;
  return e;
}

TEST(WalkingPathStage, AsksTheMissionForTheGoalOnceWhenGuidanceStarts) {
  const testing::DeviceWalk walk = testing::rendered_device_walk(1);
  int asked = 0;
  DeviceMission mission;
  mission.walking_goal = [&asked](Timestamp) {
    ++asked;
    return std::make_pair(4.0, 1.0);
  };
  auto stage = stage_for(preset("smart-cane"), walk.camera, mission);
  StateEstimate starting = localised_at(seconds_to_ns(1.0));
  starting.mode = EstimatorMode::kInitializing;
  const GuidanceOutput before = stage->update({walk.frames[0], starting});
  EXPECT_EQ(before.command.action, planning::GuidanceAction::kWait);
  EXPECT_EQ(before.command.reason, planning::GuidanceReason::kLocating);
  EXPECT_EQ(asked, 0);  // not localised yet: no pose to hold the goal
  for (int k = 0; k < 3; ++k) stage->update({walk.frames[0], localised_at(seconds_to_ns(1.1 + 0.1 * k))});
  EXPECT_EQ(asked, 1);
  const auto goal = stage->summary()["goal_W"];
  EXPECT_DOUBLE_EQ(goal[0].get<double>(), 4.0);
  EXPECT_DOUBLE_EQ(goal[1].get<double>(), 1.0);
}

TEST(WalkingPathStage, WithoutAGoalSaysWhichKeyToSet) {
  const testing::DeviceWalk walk = testing::rendered_device_walk(1);
  const std::string message =
      navaid::testing::error_message<Error>([&] { stage_for(preset("smart-cane"), walk.camera, DeviceMission{}); });
  EXPECT_NE(message.find("device.goal_start_frame_m"), std::string::npos) << message;
}

TEST(HandTargetStage, TakesTheTagFromTheConfigurationBeforeTheMission) {
  const testing::DeviceWalk walk = testing::rendered_device_walk(1);
  DeviceMission mission;
  mission.tag_id = 7;
  EXPECT_EQ(stage_for(preset("w-roma"), walk.camera, mission)->summary()["tag_id"], 7);
  EXPECT_EQ(stage_for(preset("w-roma", {"device.tag_id=12"}), walk.camera, mission)->summary()["tag_id"], 12);
  const std::string message =
      navaid::testing::error_message<Error>([&] { stage_for(preset("w-roma"), walk.camera, DeviceMission{}); });
  EXPECT_NE(message.find("device.tag_id"), std::string::npos) << message;
}

TEST(HandTargetStage, AFrameWithoutTheTagRemembersNothing) {
  const testing::DeviceWalk walk = testing::rendered_device_walk(1);
  DeviceMission mission;
  mission.tag_id = 3;
  auto stage = stage_for(preset("w-roma"), walk.camera, mission);
  const GuidanceOutput out = stage->update({walk.frames[0], walk.estimates[0]});
  EXPECT_NE(out.command.action, planning::GuidanceAction::kGo);
  EXPECT_EQ(stage->summary()["frames_detected"], 0);
}

TEST(ObstacleRumbleStage, WaitsForAScanThenRumblesAtAnObstacleAhead) {
  const testing::DeviceWalk walk = testing::rendered_device_walk(1);
  auto stage = stage_for(preset("augmented-cane"), walk.camera, DeviceMission{});
  const GuidanceOutput none = stage->update({walk.frames[0], walk.estimates[0]});
  EXPECT_EQ(none.command.action, planning::GuidanceAction::kWait);
  // An obstacle 1 m straight ahead in every bin within 10 degrees of the cane's heading.
  mapping::ObstacleScan scan;
  scan.min_bearing_rad = -M_PI / 4;
  scan.bearing_increment_rad = M_PI / 180;
  const std::size_t bins = 91;
  scan.ranges.assign(bins, std::numeric_limits<float>::infinity());
  scan.drop_off_ranges.assign(bins, std::numeric_limits<float>::infinity());
  for (std::size_t b = 35; b <= 55; ++b) scan.ranges[b] = 1.0f;
  const GuidanceOutput out = stage->update({walk.frames[0], walk.estimates[0], nullptr, &scan});
  EXPECT_NE(out.command.action, planning::GuidanceAction::kWait);
  const auto states = stage->summary()["rumble_states"];
  EXPECT_EQ(states["off"].get<int>(), 0) << states.dump();
}

TEST(RouteGuidanceStage, RoutesOverTheMissionsStreetsAndWaitsForTheRegistration) {
  const testing::DeviceWalk walk = testing::rendered_device_walk(1);
  const std::string message =
      navaid::testing::error_message<Error>([&] { stage_for(preset("elabrador"), walk.camera, DeviceMission{}); });
  EXPECT_NE(message.find("mission"), std::string::npos) << message;

  const simulation::Scenario scenario = simulation::make_scenario("route1", {});
  const simulation::OsmExport e = simulation::export_osm(scenario);
  navaid::testing::ScratchDir dir("route-stage");
  simulation::write_osm_export(e, dir.path());
  DeviceMission mission;
  mission.route = RouteMission{planning::load_osm_foot_graph(dir.path() / "map.osm"), "map.osm",
                               {e.truth.start_lat_deg, e.truth.start_lon_deg},
                               {e.truth.goal_lat_deg, e.truth.goal_lon_deg}, std::nullopt, scenario.origin};
  auto stage = stage_for(preset("elabrador"), walk.camera, mission);
  EXPECT_GT(stage->summary()["route_length_m"].get<double>(), 10.0);
  // No GPS registration on the estimate: the direction is withheld.
  const GuidanceOutput out = stage->update({walk.frames[0], walk.estimates[0]});
  EXPECT_EQ(out.command.action, planning::GuidanceAction::kWait);
}

}  // namespace
}  // namespace navaid::runtime
