// experiments' DeviceRun: runtime::Device with sinks that write the run folder; and the mission a
// recording says for the user (recording_mission.hpp), the only way ground truth reaches a device.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "device_fixture.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/experiments/device_run.hpp"
#include "navaid/experiments/recording_mission.hpp"
#include "navaid/io/targets_csv.hpp"
#include "test_support.hpp"

namespace navaid::experiments {
namespace {

namespace fs = std::filesystem;

std::size_t data_rows(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line;
  std::size_t n = 0;
  while (std::getline(in, line)) ++n;
  return n > 0 ? n - 1 : 0;
}

TEST(DeviceRun, WritesTheRunFolderFromTheDevicesSinks) {
  const testing::DeviceWalk walk = testing::rendered_device_walk(12);
  io::Recording recording;
  recording.calibration.cameras = {walk.camera};
  recording.frames = walk.frames;
  navaid::testing::ScratchDir dir("device-run");
  const Config config = Config::load(runtime::device_preset_file("smart-cane"), {"device.goal_start_frame_m=[6,0]"});
  DeviceRunOptions options;
  options.device.mapping = runtime::read_mapping_stage_options(config);
  options.figures = false;
  DeviceRun run(runtime::read_device_spec(config), config, recording, dir.path(), walk.camera, dir.path() / "run",
                MapSessionOptions{}, options);
  for (const auto& e : walk.estimates) run.device().on_estimate(e, runtime::Clock::now());
  const nlohmann::ordered_json summary = run.finish();
  const fs::path out = dir.path() / "run";
  EXPECT_EQ(data_rows(out / "device_stages.csv"), walk.frames.size());
  EXPECT_EQ(data_rows(out / "plans.csv"), summary["plans"]["made"].get<std::size_t>());
  EXPECT_EQ(data_rows(out / "guidance_timeline.csv"), summary["cues"]["timeline_entries"].get<std::size_t>());
  EXPECT_EQ(data_rows(out / "cues.csv"), summary["cues"]["events"].get<std::size_t>());
  EXPECT_EQ(data_rows(out / "latency.csv"), summary["latency"]["cues"].get<std::size_t>());
  EXPECT_EQ(data_rows(out / "map" / "timing.csv"), 4u);  // map_every 3
  EXPECT_TRUE(fs::exists(out / "map" / "map.ot"));
  EXPECT_EQ(summary["mapping"]["frames"]["mapped"], 4);
  EXPECT_FALSE(fs::exists(out / "speech.wav"));  // the Smart Cane does not speak
}

TEST(RecordingMission, SaysTheTargetFromTheRecordingsTargetsAndNamesTheKeyWhenItCannot) {
  navaid::testing::ScratchDir dir("recording-mission");
  const Config wroma = Config::load(runtime::device_preset_file("w-roma"));
  const runtime::DeviceSpec hand = runtime::read_device_spec(wroma);
  io::Recording recording;
  const std::string missing = navaid::testing::error_message<Error>(
      [&] { recording_mission(hand, wroma, recording, dir.path(), dir.path()); });
  EXPECT_NE(missing.find("device.tag_id"), std::string::npos) << missing;
  EXPECT_NE(missing.find(dir.path().string()), std::string::npos) << missing;
  io::TargetGroundTruth other, cup;
  other.name = "box";
  cup.name = "cup";
  other.tag_family = "25h9";  // another family than the detector's: not the target
  other.tag_id = 2;
  cup.tag_family = "36h11";
  cup.tag_id = 5;
  other.tag_size_m = cup.tag_size_m = 0.05;
  other.half_extents = cup.half_extents = Vec3(0.05, 0.05, 0.1);
  io::write_targets_csv(dir.path() / io::kTargetsCsv, {other, cup});
  EXPECT_EQ(recording_mission(hand, wroma, recording, dir.path(), dir.path()).tag_id, 5);

  const Config cane = Config::load(runtime::device_preset_file("smart-cane"));
  const std::string no_goal = navaid::testing::error_message<Error>(
      [&] { recording_mission(runtime::read_device_spec(cane), cane, recording, dir.path(), dir.path()); });
  EXPECT_NE(no_goal.find("device.goal_start_frame_m"), std::string::npos) << no_goal;
}

}  // namespace
}  // namespace navaid::experiments
