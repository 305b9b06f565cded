#include "navaid/simulation/sensor_rig.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "navaid/core/camera.hpp"
#include "navaid/core/errors.hpp"
#include "test_support.hpp"

namespace navaid::simulation {
namespace {

TEST(SensorRig, CameraLooksForwardPitchedDownWithImageXToTheRight) {
  for (const auto& name : mount_names()) {
    const Mount m = mount_preset(name);
    const Mat3 R = m.T_B_C().rotation();
    const double p = m.camera_pitch_rad;
    EXPECT_TRUE(R.col(2).isApprox(Vec3(std::cos(p), 0, -std::sin(p)), 1e-12)) << name;  // optical axis
    EXPECT_TRUE(R.col(0).isApprox(Vec3(0, -1, 0), 1e-12)) << name;  // image x = body right
    EXPECT_GT(R.col(1).dot(Vec3(0, 0, -1)), 0.9) << name;            // image y = mostly down
    EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
    EXPECT_TRUE(m.T_B_C().t.isApprox(m.t_B_C));
  }
}

TEST(SensorRig, MountsSetHeightAndScanningOfTheWalker) {
  WalkerConfig w;
  w.speed_mps = 1.3;
  const Mount cane = mount_preset("cane");
  const WalkerConfig c = cane.apply(w);
  EXPECT_DOUBLE_EQ(c.mount_height_m, cane.height_m);
  EXPECT_DOUBLE_EQ(c.scan_amplitude_rad, cane.scan_amplitude_rad);
  EXPECT_DOUBLE_EQ(c.scan_period_s, cane.scan_period_s);
  EXPECT_DOUBLE_EQ(c.speed_mps, 1.3);  // untouched
  EXPECT_GT(mount_preset("head").height_m, mount_preset("hand").height_m);
  EXPECT_GT(mount_preset("hand").height_m, cane.height_m);
}

TEST(SensorRig, PresetsAreValidCalibrationsWithDepth) {
  for (const auto& name : sensor_preset_names()) {
    const SensorPreset p = sensor_preset(name);
    EXPECT_NO_THROW(validate_camera_calibration(p.camera, name));
    EXPECT_EQ(p.camera.width, 640);
    EXPECT_EQ(p.camera.height, 480);
    EXPECT_DOUBLE_EQ(p.camera.rate_hz, 30.0);
    EXPECT_GT(p.camera.depth_baseline_m, 0.0);
    EXPECT_LT(p.camera.depth_min_m, p.camera.depth_max_m);
    EXPECT_GT(p.imu.rate_hz, 0.0);
  }
  // The RGBD-VIO sequences: Structure Core, depth 0.3-5 m, 500 Hz IMU.
  const SensorPreset sc = sensor_preset("structure-core");
  EXPECT_DOUBLE_EQ(sc.camera.depth_min_m, 0.3);
  EXPECT_DOUBLE_EQ(sc.camera.depth_max_m, 5.0);
  EXPECT_DOUBLE_EQ(sc.imu.rate_hz, 500.0);
}

TEST(SensorRig, UnknownNamesListTheKnownOnes) {
  const auto mount = testing::expect_throw<ConfigError>([] { mount_preset("shoulder"); });
  ASSERT_TRUE(mount);
  EXPECT_EQ(mount->key(), "mount");
  EXPECT_NE(std::string(mount->what()).find("head, cane, hand"), std::string::npos) << mount->what();
  const auto preset = testing::expect_throw<ConfigError>([] { sensor_preset("kinect"); });
  ASSERT_TRUE(preset);
  EXPECT_EQ(preset->key(), "sensor.preset");
  EXPECT_NE(std::string(preset->what()).find("structure-core"), std::string::npos);
}

}  // namespace
}  // namespace navaid::simulation
