// EstimatorDriver: the one entry of sensor events into the front end and the estimator, which
// replay, real time and closed-loop trials share.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <regex>
#include <string>
#include <vector>

#include "navaid/core/config.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/estimation/estimator_config.hpp"
#include "navaid/io/event_stream.hpp"
#include "navaid/io/navaid_recording.hpp"
#include "navaid/runtime/device.hpp"
#include "navaid/runtime/estimator_driver.hpp"
#include "navaid/runtime/estimator_pipeline.hpp"
#include "navaid/simulation/config_schema.hpp"
#include "navaid/simulation/simulator.hpp"
#include "test_support.hpp"

namespace {

using navaid::EstimatorMode;
using navaid::StateEstimate;
using navaid::runtime::EstimatorDriver;
namespace est = navaid::estimation;

// A short feature-level hand walk, made once for the suite.
const navaid::io::Recording& walk() {
  static const navaid::io::Recording rec = [] {
    navaid::testing::ScratchDir dir("runtime_driver_walk");
    const navaid::Config c = navaid::Config::parse(
        "{}", "<test>", {"scenario=lab-walk-1", "mount=hand", "simulation.mode=features", "duration=6", "seed=3"});
    const auto scenario = navaid::simulation::make_scenario(navaid::simulation::read_scenario_name(c),
                                                            navaid::simulation::read_scenario_options(c));
    const auto sim = navaid::simulation::read_simulation_config(c, scenario);
    c.reject_unknown_keys(navaid::simulation::simulation_config_schema());
    navaid::simulation::SimulateOptions options;
    options.threads = 1;
    navaid::simulation::simulate(scenario, sim, dir.path(), options);
    return navaid::io::read_navaid_recording(dir.path());
  }();
  return rec;
}

est::SlidingWindowEstimator make_estimator(const navaid::io::Recording& rec) {
  const navaid::Config c = navaid::Config::parse("{}", "<test>", {});
  return est::SlidingWindowEstimator(rec.calibration, est::read_estimator_config(c), {}, rec.origin);
}

void expect_same(const std::vector<StateEstimate>& a, const std::vector<StateEstimate>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].t, b[i].t);
    EXPECT_EQ(a[i].mode, b[i].mode);
    EXPECT_EQ(a[i].T_W_B.t, b[i].T_W_B.t) << "estimate " << i;
    EXPECT_EQ(a[i].T_W_B.q.coeffs(), b[i].T_W_B.q.coeffs()) << "estimate " << i;
    EXPECT_EQ(a[i].covariance, b[i].covariance) << "estimate " << i;
  }
}

TEST(EstimatorDriver, FeatureInputGivesTheEstimatorsOwnEstimatesAndDropsCameraFrames) {
  const auto& rec = walk();
  ASSERT_FALSE(rec.features.empty());
  est::SlidingWindowEstimator bare = make_estimator(rec);
  EstimatorDriver driver(make_estimator(rec));
  EXPECT_FALSE(driver.image_input());
  EXPECT_THROW(driver.frontend_source(), navaid::Error);
  std::vector<StateEstimate> expected, got;
  navaid::io::SensorEventStream stream(rec);
  bool frame_sent = false;
  while (auto e = stream.next()) {
    for (auto& s : bare.process(*e)) expected.push_back(s);
    if (!frame_sent && std::holds_alternative<navaid::FeatureFrame>(*e)) {
      // The recording's features stand for the images: a camera frame reaches nothing.
      navaid::RgbdFrame frame;
      frame.t = navaid::event_time(*e);
      EXPECT_FALSE(driver.frontend(frame).has_value());
      EXPECT_TRUE(driver.process(frame).empty());
      frame_sent = true;
    }
    for (auto& s : driver.process(*e)) got.push_back(s);
  }
  for (auto& s : bare.finish()) expected.push_back(s);
  for (auto& s : driver.finish()) got.push_back(s);
  ASSERT_GT(expected.size(), 20u);
  expect_same(expected, got);
  EXPECT_EQ(driver.estimator().statistics().keyframes, bare.statistics().keyframes);
}

TEST(EstimatorDriver, ReplayPerEventAndDeviceDrivingAreOneEntryPoint) {
  // navaid run replays through replay_pipeline; a caller may call process() per event; a device
  // takes the events itself (Device::add): all reach the estimator the same way and give the same
  // estimates bit for bit.
  const auto& rec = walk();
  EstimatorDriver replayed(make_estimator(rec));
  std::vector<StateEstimate> from_replay;
  const std::string camera = rec.calibration.cameras.front().name;
  navaid::runtime::PipelineInput in{rec, camera, replayed, {}, false, {}, {}, {}, {}, {}};
  in.on_record = [&](const navaid::runtime::FrameRecord& r) { from_replay.push_back(r.estimate); };
  std::size_t progress_calls = 0;
  in.on_progress = [&](std::size_t) { ++progress_calls; };
  const auto result = navaid::runtime::replay_pipeline(in);
  EXPECT_EQ(result.frames, from_replay.size());
  EXPECT_GT(progress_calls, 0u);

  EstimatorDriver per_event(make_estimator(rec));
  std::vector<StateEstimate> from_events;
  navaid::io::SensorEventStream stream(rec);
  while (auto e = stream.next())
    for (auto& s : per_event.process(*e)) from_events.push_back(s);
  for (auto& s : per_event.finish()) from_events.push_back(s);
  expect_same(from_replay, from_events);

  // A closed-loop trial hands its events to runtime::Device, which feeds its own EstimatorDriver:
  // the same estimates again, in the same order.
  const navaid::Config config =
      navaid::Config::load(navaid::runtime::device_preset_file("smart-cane"), {"device.goal_start_frame_m=[6,0]"});
  navaid::runtime::DeviceOptions options;
  options.threaded = false;
  options.mapping = navaid::runtime::read_mapping_stage_options(config);
  std::vector<StateEstimate> from_device;
  navaid::runtime::DeviceSinks sinks;
  sinks.estimate = [&](const StateEstimate& e) { from_device.push_back(e); };
  navaid::runtime::Device device(navaid::runtime::read_device_spec(config), config, rec.calibration.cameras.front(),
                                 {}, options, std::move(sinks));
  device.set_estimator(std::make_unique<EstimatorDriver>(make_estimator(rec)));
  EXPECT_THROW(device.set_estimator(std::make_unique<EstimatorDriver>(make_estimator(rec))), navaid::Error);
  navaid::io::SensorEventStream events(rec);
  while (auto e = events.next()) device.add(std::move(*e));
  device.end_of_input();
  const navaid::runtime::DeviceResult r = device.finish();
  EXPECT_FALSE(r.error);
  expect_same(from_replay, from_device);
  EXPECT_EQ(device.estimator().estimator().statistics().keyframes, replayed.estimator().statistics().keyframes);
  EXPECT_GT(device.estimator_busy_s(), 0.0);
}

TEST(EstimatorDriver, FrontEndCallsNeedImageInput) {
  const auto& rec = walk();
  EstimatorDriver driver(make_estimator(rec));
  EXPECT_THROW(driver.track(navaid::RgbdFrame{}), navaid::Error);
  EXPECT_THROW(driver.add_frontend_imu(navaid::ImuSample{}), navaid::Error);
  navaid::runtime::PipelineInput in{rec, "cam0", driver, {}, false, {}, {}, {}, {}, {}};
  EXPECT_THROW(navaid::runtime::replay_pipeline(in), navaid::Error);  // no on_record
}

TEST(GyroBiasFeedback, OnlyFromAnEstimatorThatIsTracking) {
  EXPECT_FALSE(navaid::runtime::gyro_bias_feedback({}));
  StateEstimate e;
  e.b_g = navaid::Vec3(0.01, -0.02, 0.03);
  for (EstimatorMode m : {EstimatorMode::kInitializing, EstimatorMode::kLost}) {
    e.mode = m;
    EXPECT_FALSE(navaid::runtime::gyro_bias_feedback({e}));
  }
  StateEstimate lost = e;
  e.mode = EstimatorMode::kRgbdVio;
  ASSERT_TRUE(navaid::runtime::gyro_bias_feedback({e}));
  EXPECT_EQ(*navaid::runtime::gyro_bias_feedback({e}), e.b_g);
  EXPECT_FALSE(navaid::runtime::gyro_bias_feedback({e, lost}));  // the newest one decides
}

}  // namespace

namespace {

TEST(EstimatorEntry, OnlyTheDriverFeedsTheEstimator) {
  // Replay, real time, trials and device apps reach the estimator through EstimatorDriver: a
  // second driver (an `estimator->process(...)` loop elsewhere) would miss what the driver does.
  namespace fs = std::filesystem;
  const fs::path root = NAVAID_SOURCE_DIR;
  const std::regex feeds(R"(\b\w*estimator\w*\s*(\.|->)\s*(process|finish)\s*\()");
  int files = 0;
  for (const char* room : {"apps", "core", "io", "simulation", "mapping", "planning", "interaction", "evaluation",
                           "runtime", "experiments", "examples"}) {
    if (!fs::exists(root / room)) continue;
    for (const auto& e : fs::recursive_directory_iterator(root / room)) {
      const std::string ext = e.path().extension().string();
      if (!e.is_regular_file() || (ext != ".cpp" && ext != ".hpp")) continue;
      ++files;
      if (e.path().filename() == "estimator_driver.cpp") continue;
      std::ifstream in(e.path());
      std::string line;
      for (int n = 1; std::getline(in, line); ++n)
        EXPECT_FALSE(std::regex_search(line, feeds)) << e.path().string() << ":" << n << ": " << line;
    }
  }
  EXPECT_GT(files, 300);
  // The rule itself can fail: the loops it replaced.
  EXPECT_TRUE(std::regex_search(std::string("auto more = estimator->process(SensorEvent{*fix});"), feeds));
  EXPECT_TRUE(std::regex_search(std::string("out = in.estimator.process(*pending);"), feeds));
  EXPECT_TRUE(std::regex_search(std::string("for (auto& e : in.estimator.finish()) {"), feeds));
  EXPECT_FALSE(std::regex_search(std::string("out = in.driver.estimate(*pending);"), feeds));
}

}  // namespace
