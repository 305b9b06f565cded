// runtime::Device: estimates with their frames in, everything it makes out through the sinks; the
// two-thread replay hands the sinks what the one-thread device does; a stage's failure names the
// stage and the frame; what the user asks for while it runs (a new mission, a voice command)
// takes effect at its time.
#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "device_fixture.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/runtime/device.hpp"
#include "navaid/runtime/estimator_driver.hpp"
#include "test_support.hpp"

namespace navaid::runtime {
namespace {

Config smart_cane_config() {
  return Config::load(device_preset_file("smart-cane"), {"device.goal_start_frame_m=[6,0]"});
}

/// What the sinks saw, in order.
struct Seen {
  std::vector<std::string> frames;  // t, action, reason, detail
  std::size_t mapped = 0, guidance = 0, plans = 0, cues = 0, latencies = 0;
  std::size_t maps_with_layers = 0;
};

DeviceSinks sinks_into(Seen& seen) {
  DeviceSinks k;
  k.frame = [&seen](const DeviceFrameLog& f) {
    seen.frames.push_back(std::to_string(f.t) + " " + std::string(planning::to_string(f.command.action)) + " " +
                          std::string(planning::to_string(f.command.reason)) + " " + f.command.detail);
  };
  k.map = [&seen](const RgbdFrame&, const StateEstimate&, const MappedFrame& m, const MappingStage& stage) {
    ++seen.mapped;
    if (m.result.outcome == mapping::FrameOutcome::kMapped && stage.mapper().local_maps()) ++seen.maps_with_layers;
  };
  k.guidance = [&seen](const interaction::GuidanceTimelineEntry&) { ++seen.guidance; };
  k.plan = [&seen](Timestamp, std::string_view planner, const planning::Plan&) {
    EXPECT_FALSE(planner.empty());
    ++seen.plans;
  };
  k.cue = [&seen](const interaction::CueEvent&) { ++seen.cues; };
  k.latency = [&seen](const CueLatency& l) {
    EXPECT_GE(l.latency_ms, 0.0);
    EXPECT_GE(l.event.t, l.origin);
    ++seen.latencies;
  };
  return k;
}

Seen run_device(const testing::DeviceWalk& walk, bool threaded, nlohmann::ordered_json* summary = nullptr) {
  const Config config = smart_cane_config();
  const DeviceSpec spec = read_device_spec(config);
  DeviceOptions options;
  options.threaded = threaded;
  options.mapping = read_mapping_stage_options(config);
  Seen seen;
  Device device(spec, config, walk.camera, DeviceMission{}, options, sinks_into(seen));
  for (std::size_t i = 0; i < walk.frames.size(); ++i) {
    device.add_frame(walk.frames[i]);
    device.on_estimate(walk.estimates[i], Clock::now());
  }
  StateEstimate stray = walk.estimates.back();
  stray.t += 1;  // no frame of this time: counted, not guided
  device.on_estimate(stray, Clock::now());
  DeviceResult r = device.finish();
  EXPECT_FALSE(r.error);
  if (summary) *summary = r.summary;
  EXPECT_EQ(r.events.size(), seen.cues);
  return seen;
}

TEST(Device, EveryStageHandsItsOutputToTheSinks) {
  const testing::DeviceWalk walk = testing::rendered_device_walk(12);
  nlohmann::ordered_json summary;
  const Seen seen = run_device(walk, false, &summary);
  ASSERT_EQ(seen.frames.size(), walk.frames.size());  // one log per estimate with a frame
  EXPECT_EQ(seen.mapped, 4u);                          // map_every 3: frames 0, 3, 6, 9
  EXPECT_EQ(seen.maps_with_layers, 4u);
  EXPECT_GE(seen.guidance, walk.frames.size());  // a command per frame (and system events)
  EXPECT_GT(seen.plans, 0u);                     // the walking-path generator planned on the map
  EXPECT_GT(seen.cues, 0u);                      // the wheel was driven
  EXPECT_GT(seen.latencies, 0u);
  EXPECT_EQ(summary["estimates"]["with_frame"], walk.frames.size());
  EXPECT_EQ(summary["estimates"]["without_frame"], 1);
  EXPECT_EQ(summary["plans"]["made"], seen.plans);
  EXPECT_EQ(summary["guidance"]["goal_W"][0].get<double>(), 6.0);  // 6 m ahead of the first localised pose
}

TEST(Device, TwoThreadReplayGivesTheSinksWhatOneThreadDoes) {
  const testing::DeviceWalk walk = testing::rendered_device_walk(12);
  const Seen one = run_device(walk, false);
  const Seen two = run_device(walk, true);
  EXPECT_EQ(one.frames, two.frames);
  EXPECT_EQ(one.mapped, two.mapped);
  EXPECT_EQ(one.plans, two.plans);
  EXPECT_EQ(one.cues, two.cues);
  EXPECT_EQ(one.guidance, two.guidance);
}

TEST(Device, AStageFailureNamesTheStageAndTheFrame) {
  testing::DeviceWalk walk = testing::rendered_device_walk(1);
  walk.frames[0].depth = {};
  walk.frames[0].depth_path = "/nonexistent/depth-0.png";  // the mapping stage cannot load it
  const Config config = smart_cane_config();
  DeviceOptions options;
  options.threaded = false;
  Device device(read_device_spec(config), config, walk.camera, DeviceMission{}, options, DeviceSinks{});
  device.add_frame(walk.frames[0]);
  const std::string message =
      navaid::testing::error_message<Error>([&] { device.on_estimate(walk.estimates[0], Clock::now()); });
  EXPECT_NE(message.find("mapping stage failed at frame 0"), std::string::npos) << message;
}

TEST(Device, PredictsAtTheFramesArrivalThroughTheImu) {
  const testing::DeviceWalk walk = testing::rendered_device_walk(4);
  const Config config = smart_cane_config();
  DeviceOptions options;
  options.predict_at_arrival = true;  // real time: with drop-oldest queues
  options.drop_when_full = true;
  options.mapping = read_mapping_stage_options(config);
  DeviceSinks sinks;
  std::vector<Timestamp> commands;
  sinks.frame = [&commands](const DeviceFrameLog& f) { commands.push_back(f.t); };
  Device device(read_device_spec(config), config, walk.camera, DeviceMission{}, options, std::move(sinks));
  for (const auto& f : walk.frames) device.add_frame(f);
  // Walking at 1 m/s without rotation: the accelerometer feels gravity only.
  for (Timestamp t = seconds_to_ns(0.9); t <= seconds_to_ns(1.5); t += seconds_to_ns(0.005))
    device.add_imu(ImuSample{t, Vec3::Zero(), Vec3(0, 0, 9.81)});
  device.on_frame_arrival(walk.frames[0].t, Clock::now());  // nothing solved yet: skipped
  device.on_estimate(walk.estimates[0], Clock::now());
  for (std::size_t i = 1; i < walk.frames.size(); ++i) device.on_frame_arrival(walk.frames[i].t, Clock::now());
  const DeviceResult r = device.finish();
  EXPECT_FALSE(r.error);
  // Frames 1..3 were guided from the first estimate carried forward 0.1, 0.2, 0.3 s.
  EXPECT_EQ(commands, (std::vector<Timestamp>{walk.frames[1].t, walk.frames[2].t, walk.frames[3].t}));
  EXPECT_EQ(r.summary["latency"]["prediction_span_ms"]["frames"], 3);
  EXPECT_NEAR(r.summary["latency"]["prediction_span_ms"]["max_ms"].get<double>(), 300.0, 1e-6);
}

/// The Smart Cane with its goal from the mission (no device.goal_start_frame_m), two threads.
struct MissionRun {
  std::vector<interaction::SystemEvent> said;  // the voice commands the cue session heard
  nlohmann::ordered_json summary;
  std::exception_ptr error;
};

template <class Ask>
MissionRun run_with_user(const testing::DeviceWalk& walk, DeviceMission mission, Ask&& ask) {
  const Config config = Config::load(device_preset_file("smart-cane"), {});
  DeviceOptions options;
  options.mapping = read_mapping_stage_options(config);
  MissionRun run;
  DeviceSinks sinks;
  sinks.guidance = [&run](const interaction::GuidanceTimelineEntry& entry) {
    if (const auto* e = std::get_if<interaction::SystemEvent>(&entry);
        e && e->kind == interaction::SystemEventKind::kVoiceCommand)
      run.said.push_back(*e);
  };
  Device device(read_device_spec(config), config, walk.camera, mission, options, std::move(sinks));
  ask(device);
  for (std::size_t i = 0; i < walk.frames.size(); ++i) {
    device.add_frame(walk.frames[i]);
    device.on_estimate(walk.estimates[i], Clock::now());
  }
  DeviceResult r = device.finish();
  run.summary = r.summary;
  run.error = r.error;
  return run;
}

DeviceMission walking_goal(double forward, double left) {
  DeviceMission m;
  m.walking_goal = [forward, left](Timestamp) { return std::make_pair(forward, left); };
  return m;
}

TEST(Device, ANewMissionRebuildsTheGuidanceAtItsTime) {
  const testing::DeviceWalk walk = testing::rendered_device_walk(12);
  // Walking +x at 1 m/s from x = 0: frame 6 stands at x = 0.6 m.
  const MissionRun run = run_with_user(walk, walking_goal(6, 0), [&](Device& device) {
    device.set_mission(walk.frames[6].t - 1, walking_goal(2, 1));  // handled at frame 6
  });
  ASSERT_FALSE(run.error);
  const auto& g = run.summary["guidance"];
  ASSERT_EQ(g["earlier_missions"].size(), 1u);
  EXPECT_NEAR(g["earlier_missions"][0]["goal_W"][0].get<double>(), 6.0, 1e-9);
  EXPECT_NEAR(g["goal_W"][0].get<double>(), 0.6 + 2.0, 1e-6);  // anchored where the user stood
  EXPECT_NEAR(g["goal_W"][1].get<double>(), 1.0, 1e-6);
  EXPECT_TRUE(run.said.empty());
}

TEST(Device, AnswersTheUsersVoiceAtTheNextEstimate) {
  const testing::DeviceWalk walk = testing::rendered_device_walk(12);
  DeviceMission mission = walking_goal(6, 0);
  std::vector<std::string> asked;
  mission.place = [&asked](std::string_view place, const StateEstimate& now) -> std::optional<DeviceMission> {
    asked.emplace_back(place);
    if (place != "kitchen") return std::nullopt;
    DeviceMission m = walking_goal(0, 2);
    EXPECT_NEAR(now.T_W_B.t.x(), 0.9, 1e-9);  // resolved from where the user is when it is handled
    return m;
  };
  interaction::VoiceCommand repeat{interaction::VoiceCommand::Kind::kRepeat, "", "repeat", 1.0};
  interaction::VoiceCommand garden{interaction::VoiceCommand::Kind::kGoTo, "garden", "go to garden", 1.0};
  interaction::VoiceCommand kitchen{interaction::VoiceCommand::Kind::kGoTo, "kitchen", "go to kitchen", 1.0};
  const MissionRun run = run_with_user(walk, mission, [&](Device& device) {
    device.on_voice_command(walk.frames[9].t - 5, kitchen);  // out of order: sorted by time
    device.on_voice_command(walk.frames[2].t, repeat);
    device.on_voice_command(walk.frames[4].t - 5, garden);
  });
  ASSERT_FALSE(run.error);
  ASSERT_EQ(run.said.size(), 3u);
  EXPECT_EQ(run.said[0].value, "repeat");
  EXPECT_EQ(run.said[0].t, walk.frames[2].t);
  EXPECT_EQ(run.said[1].value, "not understood");  // no such place
  EXPECT_EQ(run.said[1].t, walk.frames[4].t);
  EXPECT_EQ(run.said[2].value, "go to kitchen");
  EXPECT_EQ(run.said[2].t, walk.frames[9].t);
  EXPECT_EQ(asked, (std::vector<std::string>{"garden", "kitchen"}));
  const auto& g = run.summary["guidance"];
  ASSERT_EQ(g["earlier_missions"].size(), 1u);
  EXPECT_NEAR(g["goal_W"][0].get<double>(), 0.9, 1e-6);  // 2 m to the left of frame 9's pose
  EXPECT_NEAR(g["goal_W"][1].get<double>(), 2.0, 1e-6);
}

TEST(Device, SensorEventsNeedAnEstimator) {
  const testing::DeviceWalk walk = testing::rendered_device_walk(1);
  const Config config = smart_cane_config();
  DeviceOptions options;
  options.threaded = false;
  Device device(read_device_spec(config), config, walk.camera, DeviceMission{}, options, DeviceSinks{});
  const std::string message = navaid::testing::error_message<Error>([&] { device.add(walk.frames[0]); });
  EXPECT_NE(message.find("sensor events need an estimator"), std::string::npos) << message;
  EXPECT_THROW(device.estimator(), Error);
  EXPECT_THROW(device.set_estimator(nullptr), Error);
}

}  // namespace
}  // namespace navaid::runtime
