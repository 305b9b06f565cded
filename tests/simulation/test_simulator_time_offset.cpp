// The simulated camera-IMU time offset: camera frames are stamped in the camera clock
// (t_imu = t_cam + offset), and calibration.yaml carries the calibrated value.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "navaid/core/camera.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/io/image_io.hpp"
#include "navaid/io/navaid_recording.hpp"
#include "navaid/simulation/config_schema.hpp"
#include "navaid/simulation/simulator.hpp"
#include "test_support.hpp"

namespace navaid::simulation {
namespace {

// Noise-free corridor walk with a 25 Hz camera: frame times (multiples of 40 ms from -1 s) and the
// 200 Hz IMU / ground-truth grid (multiples of 5 ms) share instants, so with an offset of a
// multiple of 5 ms every frame's exposure has a ground-truth sample of its own.
struct OffsetCorridor {
  testing::ScratchDir dir;
  Scenario scenario = make_scenario("corridor");
  SimulationConfig config;
  io::Recording rec;
  std::map<Timestamp, SE3> groundtruth;  // T_W_B by IMU time

  OffsetCorridor(const std::string& name, const std::vector<std::string>& overrides) : dir(name) {
    std::vector<std::string> all = {"seed=3", "sensor.noise=false", "sensor.camera.rate=25", "simulation.people=false"};
    all.insert(all.end(), overrides.begin(), overrides.end());
    const Config c = Config::parse("{}", "<test>", all);
    config = read_simulation_config(c, scenario);
    c.reject_unknown_keys(simulation_config_schema());
    SimulateOptions options;
    options.threads = 2;
    simulate(scenario, config, dir.path(), options);
    rec = io::read_navaid_recording(dir.path());
    for (const auto& g : rec.groundtruth) groundtruth.emplace(g.t, g.T_W_B);
  }

  // The camera pose from the ground-truth sample at IMU time t (which must exist).
  SE3 T_W_C(Timestamp t) const {
    const auto it = groundtruth.find(t);
    EXPECT_NE(it, groundtruth.end()) << "no ground truth at " << t;
    return (it == groundtruth.end() ? SE3::identity() : it->second) * config.camera.T_B_C;
  }
  bool has_groundtruth(Timestamp t) const { return groundtruth.count(t) > 0; }
};

TEST(SimulatorTimeOffset, FeatureFrameStampedTShowsTheSceneFromThePoseAtTPlusOffset) {
  const Timestamp offset_ns = 20'000'000;  // 20 ms: the camera clock runs behind the IMU's
  const OffsetCorridor sim("simulator_time_offset_features",
                           {"duration=3", "simulation.mode=features", "sensor.camera.time_offset=0.02",
                            "sensor.camera.time_offset_calibrated=0.015"});
  ASSERT_EQ(sim.rec.calibration.cameras.size(), 1u);
  EXPECT_DOUBLE_EQ(sim.rec.calibration.cameras[0].time_offset_s, 0.015);  // what calibration.yaml says
  ASSERT_EQ(sim.rec.features.size(), 76u);                                // 3 s at 25 Hz, both ends
  EXPECT_EQ(sim.rec.features.front().t, kSimulationEpoch - 1'000'000'000 - offset_ns);

  const auto camera = make_camera_model(sim.rec.calibration.cameras[0]);
  std::size_t checked = 0, moving = 0;
  double err_offset_max = 0, err_stamp_sum = 0;
  for (const FeatureFrame& frame : sim.rec.features) {
    const SE3 T_C_W = sim.T_W_C(frame.t + offset_ns).inverse();
    // The same frame explained by the pose at its stamp (the IMU clock misread as the camera's).
    const bool stamp_pose = sim.has_groundtruth(frame.t) && frame.t > kSimulationEpoch + 200'000'000;
    const SE3 T_C_W_stamp = stamp_pose ? sim.T_W_C(frame.t).inverse() : SE3::identity();
    for (const FeatureObservation& o : frame.features) {
      ASSERT_LT(o.track_id, sim.rec.landmarks.size());
      const Vec3 p_W = sim.rec.landmarks[o.track_id].p_W;
      const Vec3 p_C = T_C_W * p_W;
      const auto uv = camera->project(p_C);
      ASSERT_TRUE(uv.has_value());
      err_offset_max = std::max(err_offset_max, (*uv - o.uv).norm());
      if (o.depth_m) {
        EXPECT_NEAR(*o.depth_m, p_C.z(), 1e-4);
      }
      ++checked;
      if (stamp_pose) {
        if (const auto uv_stamp = camera->project(T_C_W_stamp * p_W)) {
          err_stamp_sum += (*uv_stamp - o.uv).norm();
          ++moving;
        }
      }
    }
  }
  ASSERT_GT(checked, 2000u);
  ASSERT_GT(moving, 1000u);
  // Exact (the ground-truth file keeps every bit); 20 ms of walking moves features by pixels.
  EXPECT_LT(err_offset_max, 1e-9);
  EXPECT_GT(err_stamp_sum / static_cast<double>(moving), 1.0);
}

TEST(SimulatorTimeOffset, ImageStampedTIsRenderedFromThePoseAtTPlusOffset) {
  const Timestamp offset_ns = -30'000'000;  // the camera clock runs ahead
  const OffsetCorridor sim("simulator_time_offset_images",
                           {"duration=2.2", "sensor.camera.resolution=[80,60]", "sensor.camera.time_offset=-0.03"});
  EXPECT_DOUBLE_EQ(sim.rec.calibration.cameras[0].time_offset_s, -0.03);  // calibrated = true by default
  ASSERT_EQ(sim.rec.frames.size(), 56u);
  const auto camera = make_camera_model(sim.config.camera);
  std::size_t checked = 0, off = 0;
  for (std::size_t k = 40; k < sim.rec.frames.size(); k += 2) {  // walking (the still start ends at 1 s)
    const RgbdFrame& frame = sim.rec.frames[k];
    EXPECT_EQ(frame.t, kSimulationEpoch - 1'000'000'000 + static_cast<Timestamp>(k) * 40'000'000 - offset_ns);
    const ImageF32 depth = io::read_depth_png(frame.depth_path, frame.depth_png_scale_m);
    const SE3 T_W_C = sim.T_W_C(frame.t + offset_ns);
    const SE3 T_W_C_stamp = sim.T_W_C(frame.t);
    const RayCaster world(world_at(sim.scenario, ns_to_seconds(frame.t + offset_ns - kSimulationEpoch)));
    for (int y = 0; y < depth.height; ++y)
      for (int x = 0; x < depth.width; ++x) {
        const float z = depth.at(x, y);
        if (z == 0.0f) continue;
        const Vec3 b = *camera->unproject(CameraModel::Vec2(x, y));
        const auto hit = world.cast(T_W_C.t, T_W_C.q * b);
        ASSERT_TRUE(hit);
        // 0.5 mm of the millimetre PNG, 0.1 mm render quantum, ground-truth decimals.
        EXPECT_NEAR(z, hit->distance * b.z(), 0.7e-3) << "pixel " << x << "," << y << " of frame " << k;
        const auto hit_stamp = world.cast(T_W_C_stamp.t, T_W_C_stamp.q * b);
        off += !hit_stamp || std::abs(z - hit_stamp->distance * b.z()) > 5e-3;
        ++checked;
      }
  }
  ASSERT_GT(checked, 10000u);
  EXPECT_GT(off, checked / 4);  // 30 ms earlier the camera saw a different depth in most pixels
}

TEST(SimulatorTimeOffset, OffsetsBeyondATenthOfASecondAreRejected) {
  const Scenario scenario = make_scenario("corridor");
  for (const char* bad : {"sensor.camera.time_offset=0.2", "sensor.camera.time_offset=-0.11",
                                "sensor.camera.time_offset_calibrated=0.15"}) {
    const Config c = Config::parse("{}", "<test>", {bad});
    EXPECT_THROW(read_simulation_config(c, scenario), ConfigError) << bad;
  }
  const Config c = Config::parse("{}", "<test>", {"sensor.camera.time_offset=-0.1"});
  const SimulationConfig s = read_simulation_config(c, scenario);
  EXPECT_DOUBLE_EQ(s.camera_time_offset_s, -0.1);
  EXPECT_DOUBLE_EQ(s.camera.time_offset_s, -0.1);
  const SimulationConfig none = read_simulation_config(Config::parse("{}", "<test>", {}), scenario);
  EXPECT_EQ(none.camera_time_offset_s, 0.0);
  EXPECT_EQ(none.camera.time_offset_s, 0.0);
}

}  // namespace
}  // namespace navaid::simulation
