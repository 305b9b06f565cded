// The simulator end to end (library API): every scenario renders, and the written recording's
// depth and labels agree with the world geometry seen from the ground-truth pose.
#include "navaid/simulation/simulator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "navaid/core/camera.hpp"
#include "navaid/io/image_io.hpp"
#include "navaid/io/navaid_recording.hpp"
#include "navaid/simulation/config_schema.hpp"
#include "test_support.hpp"

namespace navaid::simulation {
namespace {

TEST(Simulator, EveryScenarioRendersFromItsPath) {
  for (const auto& name : scenario_names()) {
    const Scenario scenario = make_scenario(name);
    const RayCaster caster(scenario.world);
    const Mount mount = mount_preset(scenario.default_mount);
    WalkerConfig walker = mount.apply(WalkerConfig{});
    walker.ground_z_m = scenario.ground_z_m;
    const WalkerTrajectory trajectory(scenario.path, walker);
    const CameraCalibration calib = rescale_camera(sensor_preset(mount.default_sensor).camera, 80, 60);
    const auto camera = make_camera_model(calib);
    const RgbdRenderer renderer(caster, *camera);
    RenderOptions options;
    options.max_depth = calib.depth_max_m;
    for (double t : {2.0, 0.5 * trajectory.duration()}) {
      const RenderedFrame f = renderer.render(trajectory.state(t).T_W_B * mount.T_B_C(), options);
      std::size_t valid = 0;
      std::set<int> classes;
      for (std::size_t i = 0; i < f.depth.pixels.size(); ++i) {
        valid += f.depth.pixels[i] > 0;
        classes.insert(f.labels.pixels[i]);
      }
      EXPECT_GT(valid, f.depth.pixels.size() / 5) << name << " at t = " << t;
      EXPECT_GE(classes.size(), 2u) << name << " at t = " << t;
    }
  }
}

struct SimulatedCorridor {
  testing::ScratchDir dir{"simulator_corridor"};
  Scenario scenario = make_scenario("corridor");
  SimulationConfig config;
  io::Recording rec;

  explicit SimulatedCorridor(const std::vector<std::string>& overrides) {
    std::vector<std::string> all = {"duration=2", "seed=4", "sensor.camera.resolution=[160,120]"};
    all.insert(all.end(), overrides.begin(), overrides.end());
    const Config c = Config::parse("{}", "<test>", all);
    config = read_simulation_config(c, scenario);
    c.reject_unknown_keys(simulation_config_schema());
    SimulateOptions options;
    options.threads = 2;
    simulate(scenario, config, dir.path(), options);
    rec = io::read_navaid_recording(dir.path());
  }

  // Pose of the camera at a frame, from the same trajectory the simulator walked.
  SE3 T_W_C(Timestamp t) const {
    WalkerConfig w = config.walker;
    w.ground_z_m = scenario.ground_z_m;
    const WalkerTrajectory trajectory(scenario.path, w);
    return trajectory.state(ns_to_seconds(t - kSimulationEpoch)).T_W_B * config.camera.T_B_C;
  }
};

TEST(Simulator, EveryValidDepthPixelBackProjectsOntoTheWorldWithinTheNoiseModel) {
  const SimulatedCorridor sim({});
  ASSERT_EQ(sim.rec.frames.size(), 61u);
  const auto camera = make_camera_model(sim.config.camera);
  std::size_t checked = 0;
  double sum_sq = 0;
  for (std::size_t k = 0; k < sim.rec.frames.size(); k += 6) {
    const RgbdFrame& frame = sim.rec.frames[k];
    const ImageF32 depth = io::read_depth_png(frame.depth_path, frame.depth_png_scale_m);
    const SE3 T_W_C = sim.T_W_C(frame.t);
    const RayCaster world(world_at(sim.scenario, ns_to_seconds(frame.t - kSimulationEpoch)));
    for (int y = 0; y < depth.height; ++y)
      for (int x = 0; x < depth.width; ++x) {
        const float z = depth.at(x, y);
        if (z == 0.0f) continue;
        ASSERT_GE(z, sim.config.camera.depth_min_m);
        ASSERT_LE(z, sim.config.camera.depth_max_m);
        const Vec3 b = *camera->unproject(CameraModel::Vec2(x, y));
        const auto hit = world.cast(T_W_C.t, T_W_C.q * b);
        ASSERT_TRUE(hit) << "depth " << z << " where the ray hits nothing, pixel " << x << "," << y;
        const double z_true = hit->distance * b.z();
        // 6 sigma of the disparity noise, plus 0.5 mm of the millimetre PNG and the 0.1 mm render quantum.
        const double sigma = depth_sigma(z_true, sim.config.rgbd_noise);
        EXPECT_LE(std::abs(z - z_true), 6.0 * sigma + 0.6e-3) << "pixel " << x << "," << y << " of frame " << k;
        sum_sq += (z - z_true) * (z - z_true) / (sigma * sigma + 1e-12);
        ++checked;
      }
  }
  ASSERT_GT(checked, 20000u);
  // The normalized error has unit variance (quantization adds ~1 % at these depths).
  EXPECT_NEAR(sum_sq / checked, 1.0, 0.1);
}

TEST(Simulator, LabelsAreTheClassOfThePrimitiveHitWhenTheNetworkIsPerfect) {
  const SimulatedCorridor sim({"sensor.labels.noise=false"});
  const auto camera = make_camera_model(sim.config.camera);
  for (std::size_t k = 0; k < sim.rec.frames.size(); k += 10) {
    const RgbdFrame& frame = sim.rec.frames[k];
    const ImageU8 labels = io::read_label_image(frame.labels_path);
    const SE3 T_W_C = sim.T_W_C(frame.t);
    const RayCaster world(world_at(sim.scenario, ns_to_seconds(frame.t - kSimulationEpoch)));
    std::size_t mismatches = 0;
    for (int y = 0; y < labels.height; ++y)
      for (int x = 0; x < labels.width; ++x) {
        const auto hit = world.cast(T_W_C.t, T_W_C.q * *camera->unproject(CameraModel::Vec2(x, y)));
        const auto expected = hit ? hit->semantic : SemanticClass::kSky;
        mismatches += labels.at(x, y) != static_cast<std::uint8_t>(expected);
      }
    EXPECT_EQ(mismatches, 0u) << "frame " << k;
  }
}

}  // namespace
}  // namespace navaid::simulation
