// The device's mapping stage: frames into the map with their estimates, the BYU obstacle scan of
// each frame when enabled, and the segmentation link's outages (labels dropped, changes handed
// on as system events).
#include <gtest/gtest.h>

#include <variant>

#include "device_fixture.hpp"
#include "navaid/runtime/mapping_stage.hpp"

namespace navaid::runtime {
namespace {

TEST(MappingStage, MapsFramesAndScansObstaclesWhenEnabled) {
  const testing::DeviceWalk walk = testing::rendered_device_walk(3);
  const Config config = Config::parse("mapping: {obstacles: {enabled: true}}");
  const MappingStageOptions options = read_mapping_stage_options(config);
  ASSERT_TRUE(options.obstacles);
  MappingStage stage(mapping::read_mapper_config(config), walk.camera, options);
  for (std::size_t i = 0; i < walk.frames.size(); ++i) {
    const MappedFrame m = stage.add(walk.frames[i], walk.estimates[i]);
    EXPECT_EQ(m.result.outcome, mapping::FrameOutcome::kMapped);
    ASSERT_TRUE(m.scan);
    EXPECT_EQ(m.scan->t, walk.frames[i].t);
    EXPECT_GT(m.scan->counters.obstacle_points, 0u);  // the bench ahead
  }
  EXPECT_EQ(stage.mapper().counters().mapped, 3u);
  EXPECT_TRUE(stage.last_obstacle_scan());
  EXPECT_EQ(stage.link(), nullptr);
}

TEST(MappingStage, WithoutObstaclesThereIsNoScan) {
  const testing::DeviceWalk walk = testing::rendered_device_walk(1);
  MappingStage stage(mapping::read_mapper_config(Config()), walk.camera, MappingStageOptions{});
  EXPECT_FALSE(stage.add(walk.frames[0], walk.estimates[0]).scan);
  EXPECT_FALSE(stage.last_obstacle_scan());
}

TEST(MappingStage, AnOutageDropsTheLabelsAndIsHandedOnAsSystemEvents) {
  const testing::DeviceWalk walk = testing::rendered_device_walk(30);  // 1.0 .. 3.9 s
  // The server is down from 0.5 s to 1.5 s after the start (t = 0): the edge notices at its
  // next probe and hears it back after the outage.
  const Config config = Config::parse("mapping: {network: {outages: [0.5, 1.5], check_period_s: 0.2, timeout_s: 0.1}}");
  MappingStageOptions options = read_mapping_stage_options(config);
  ASSERT_TRUE(options.network);
  MappingStage stage(mapping::read_mapper_config(config), walk.camera, options);
  std::vector<mapping::NetworkChange> changes;
  std::size_t dropped = 0;
  for (std::size_t i = 0; i < walk.frames.size(); ++i) {
    const MappedFrame m = stage.add(walk.frames[i], walk.estimates[i]);
    dropped += m.labels_dropped ? 1 : 0;
    changes.insert(changes.end(), m.network_changes.begin(), m.network_changes.end());
  }
  ASSERT_EQ(changes.size(), 2u);
  EXPECT_EQ(changes[0].kind, mapping::NetworkChangeKind::kLost);
  EXPECT_EQ(changes[1].kind, mapping::NetworkChangeKind::kRestored);
  EXPECT_GT(dropped, 0u);
  EXPECT_EQ(stage.frames_geometry_only(), dropped);
  const auto lost = std::get<interaction::SystemEvent>(network_event(changes[0]));
  EXPECT_EQ(lost.kind, interaction::SystemEventKind::kNetworkLost);
  EXPECT_EQ(lost.t, changes[0].t);
  EXPECT_EQ(std::get<interaction::SystemEvent>(network_event(changes[1])).kind,
            interaction::SystemEventKind::kNetworkRestored);
}

}  // namespace
}  // namespace navaid::runtime
