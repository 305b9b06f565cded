// ImageFeatureSource: gyro integration (known answers), frontend.* keys, the camera rotation it
// predicts (against a walker's true motion), and that it hands the tracker's output on unchanged.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "navaid/core/camera.hpp"
#include "navaid/core/config.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/estimation/config_schema.hpp"
#include "navaid/estimation/frontend/image_feature_source.hpp"
#include "navaid/simulation/sensor_rig.hpp"
#include "navaid/simulation/walker_trajectory.hpp"
#include "test_support.hpp"

namespace navaid::estimation {
namespace {

using navaid::testing::error_message;
using navaid::testing::expect_throw;

double angle_between(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return so3_log(Quat(a.transpose() * b)).norm();
}

ImuSample gyro_sample(Timestamp t, const Vec3& w) {
  ImuSample s;
  s.t = t;
  s.gyro = w;
  return s;
}

TEST(IntegrateGyro, ConstantRateIsOneExponential) {
  const Vec3 w(0.3, -0.2, 0.5);
  std::vector<ImuSample> imu;
  for (int k = 0; k <= 20; ++k) imu.push_back(gyro_sample(5'000'000LL * k, w));
  // Interval ends between samples and beyond the last one (the rate is held there).
  const Timestamp t0 = 3'000'000, t1 = 120'000'000;
  const Eigen::Matrix3d expected = so3_exp(w * 0.117).toRotationMatrix();
  EXPECT_LT(angle_between(integrate_gyro(imu, t0, t1), expected), 1e-12);
  // The bias is subtracted from every rate.
  const Vec3 bias(0.01, 0.02, -0.03);
  EXPECT_LT(angle_between(integrate_gyro(imu, t0, t1, bias), so3_exp((w - bias) * 0.117).toRotationMatrix()), 1e-12);
  EXPECT_TRUE(integrate_gyro(imu, t1, t0).isIdentity(0.0));
  EXPECT_TRUE(integrate_gyro({}, t0, t1).isIdentity(0.0));
}

TEST(IntegrateGyro, LinearRateAboutAFixedAxisIsExactOnIrregularSamples) {
  // w(t) = (a + b t) n: the angle is a T + b (t1^2 - t0^2) / 2 whatever the sample spacing.
  const Vec3 n = Vec3(1, 2, -2).normalized();
  const double a = 0.4, b = 3.0;
  std::mt19937 rng(3);
  std::uniform_int_distribution<Timestamp> step(1'000'000, 9'000'000);
  std::vector<ImuSample> imu;
  for (Timestamp t = 0; t < 300'000'000; t += step(rng)) imu.push_back(gyro_sample(t, (a + b * 1e-9 * t) * n));
  const double t0 = 0.0123456, t1 = 0.2345678;
  const double angle = a * (t1 - t0) + 0.5 * b * (t1 * t1 - t0 * t0);
  const Eigen::Matrix3d R = integrate_gyro(imu, seconds_to_ns(t0), seconds_to_ns(t1));
  EXPECT_LT(angle_between(R, so3_exp(angle * n).toRotationMatrix()), 1e-12);
}

TEST(FrontendKeys, DefaultsOverridesAndErrorsNameTheKey) {
  const FrontendConfig defaults = read_frontend_config(Config());
  EXPECT_EQ(defaults.max_features, FrontendConfig{}.max_features);
  EXPECT_EQ(defaults.imu_prediction, FrontendConfig{}.imu_prediction);
  EXPECT_EQ(defaults.klt_window_px, FrontendConfig{}.klt_window_px);

  const Config c = Config::parse("frontend:\n  max_features: 80\n  fb_threshold_px: 0.5\n", "fe.yaml",
                                 {"frontend.imu_prediction=false", "frontend.depth_patch_size=5"});
  const FrontendConfig f = read_frontend_config(c);
  EXPECT_EQ(f.max_features, 80);
  EXPECT_DOUBLE_EQ(f.fb_threshold_px, 0.5);
  EXPECT_FALSE(f.imu_prediction);
  EXPECT_EQ(f.depth_patch_size, 5);
  c.reject_unknown_keys(frontend_config_schema());  // every key above is a front-end key

  const auto bad = expect_throw<ConfigError>(
      [] { read_frontend_config(Config::parse("{}", "<defaults>", {"frontend.klt_window_px=4"})); });
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->key(), "frontend.klt_window_px");
  EXPECT_NE(std::string(bad->what()).find("--set"), std::string::npos) << bad->what();
  EXPECT_NE(std::string(bad->what()).find("odd integer >= 5"), std::string::npos) << bad->what();
  // Cross-key rule from validate(): detect_min_missing <= max_features.
  const auto cross = expect_throw<ConfigError>([] {
    read_frontend_config(Config::parse("frontend: {max_features: 20, detect_min_missing: 30}", "fe.yaml"));
  });
  ASSERT_TRUE(cross);
  EXPECT_EQ(cross->key(), "frontend.detect_min_missing");
  EXPECT_EQ(cross->file(), "fe.yaml");
  const std::string wrong_type = error_message<ConfigError>(
      [] { read_frontend_config(Config::parse("{}", "<defaults>", {"frontend.ransac=maybe"})); });
  EXPECT_NE(wrong_type.find("frontend.ransac"), std::string::npos) << wrong_type;
}

// A small camera looking at a blocky random texture that slides sideways a few pixels per frame.
constexpr int kW = 160, kH = 120;

CameraCalibration small_camera(const std::string& name = "cam0") {
  CameraCalibration c;
  c.name = name;
  c.width = kW;
  c.height = kH;
  c.fx = c.fy = 120.0;
  c.cx = 79.5;
  c.cy = 59.5;
  return c;
}

ImageU8 texture_frame(int shift_px) {
  std::mt19937 rng(17);
  std::uniform_int_distribution<int> grey(20, 235);
  constexpr int kBlock = 6, kCols = (kW + 64) / kBlock + 1, kRows = kH / kBlock + 1;
  std::vector<int> blocks(static_cast<std::size_t>(kCols * kRows));
  for (int& b : blocks) b = grey(rng);
  ImageU8 img(kW, kH);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const int u = x + shift_px + 32;
      img.at(x, y) = static_cast<std::uint8_t>(blocks[static_cast<std::size_t>((y / kBlock) * kCols + u / kBlock)]);
    }
  return img;
}

RgbdFrame frame_at(std::uint64_t k, const std::string& camera = "cam0") {
  RgbdFrame f;
  f.index = k;
  f.t = static_cast<Timestamp>(k) * 33'333'333 + 1'000'000'000;
  f.camera = camera;
  return f;
}

TEST(ImageFeatureSource, HandsOnTheTrackersFramesKeepsTimesAndSkipsOtherCameras) {
  RigCalibration rig;
  rig.cameras = {small_camera("left"), small_camera("right")};
  FrontendConfig config;
  config.max_features = 40;
  config.min_distance_px = 10;
  config.imu_prediction = false;
  config.depth_edge_margin_px = 0;

  int loads = 0;
  ImageFeatureSource source(rig, config, "", [&loads](RgbdFrame& f) {
    ++loads;
    f.intensity = texture_frame(static_cast<int>(3 * f.index));
  });
  EXPECT_EQ(source.camera_name(), "left");
  FeatureTracker reference(make_camera_model(small_camera("left")), config);

  for (std::uint64_t k = 0; k < 6; ++k) {
    // The other camera's frame is skipped without loading or tracking anything.
    EXPECT_FALSE(source.process(frame_at(k, "right")));
    // An IMU sample passes through unchanged.
    const auto imu = source.process(gyro_sample(frame_at(k).t - 1000, Vec3::Zero()));
    ASSERT_TRUE(imu && std::holds_alternative<ImuSample>(*imu));

    const auto out = source.process(frame_at(k, "left"));
    ASSERT_TRUE(out && std::holds_alternative<FeatureFrame>(*out));
    const auto& features = std::get<FeatureFrame>(*out);
    RgbdFrame loaded = frame_at(k, "left");
    loaded.intensity = texture_frame(static_cast<int>(3 * k));
    const FeatureFrame expected = reference.track(loaded);
    EXPECT_EQ(features.t, frame_at(k).t);
    EXPECT_EQ(features.camera, "left");
    ASSERT_EQ(features.features.size(), expected.features.size());
    for (std::size_t i = 0; i < expected.features.size(); ++i) {
      EXPECT_EQ(features.features[i].track_id, expected.features[i].track_id);
      EXPECT_EQ(features.features[i].uv, expected.features[i].uv);
    }
    if (k > 0) {
      EXPECT_GT(source.stats().tracked, 20u) << "frame " << k;
    }
    EXPECT_FALSE(source.last_rotation());  // prediction off
  }
  EXPECT_EQ(loads, 6);
  EXPECT_EQ(source.frames_tracked(), 6u);

  // Frames whose pixels are already there are not loaded again.
  RgbdFrame preloaded = frame_at(6);
  preloaded.camera = "left";
  preloaded.intensity = texture_frame(18);
  ASSERT_TRUE(source.track(preloaded));
  EXPECT_EQ(loads, 6);
}

TEST(ImageFeatureSource, ClearErrors) {
  RigCalibration rig;
  rig.cameras = {small_camera()};
  ImageFeatureSource no_loader(rig, FrontendConfig{});
  const std::string msg = error_message<Error>([&] { no_loader.track(frame_at(0)); });
  EXPECT_NE(msg.find("no intensity loaded and no image loader"), std::string::npos) << msg;

  const auto missing = expect_throw<ConfigError>([&] { ImageFeatureSource(rig, FrontendConfig{}, "cam7"); });
  ASSERT_TRUE(missing);
  EXPECT_NE(std::string(missing->what()).find("cam7"), std::string::npos);
  EXPECT_TRUE(expect_throw<ConfigError>([] { ImageFeatureSource(RigCalibration{}, FrontendConfig{}); }));
  FrontendConfig bad;
  bad.klt_window_px = 4;
  EXPECT_TRUE(expect_throw<ConfigError>([&] { ImageFeatureSource(rig, bad); }));

  no_loader.add_imu(gyro_sample(2'000, Vec3::Zero()));
  const std::string order = error_message<Error>([&] { no_loader.add_imu(gyro_sample(1'000, Vec3::Zero())); });
  EXPECT_NE(order.find("time order"), std::string::npos) << order;
}

// The predicted rotation is the true camera rotation between frames: 200 Hz gyro samples of a
// walker's exact angular rate, hand mount (a camera rotated against the body), camera time offset.
TEST(ImageFeatureSource, PredictedRotationIsTheTrueCameraRotation) {
  const simulation::Mount mount = simulation::mount_preset("hand");
  simulation::WalkerConfig walker = mount.apply(simulation::WalkerConfig{});
  walker.scan_amplitude_rad = 0.4;  // plenty of yaw besides the gait's roll and pitch
  const simulation::WalkerTrajectory trajectory({{0, 0}, {6, 0}, {6, 5}}, walker);

  RigCalibration rig;
  CameraCalibration cam = small_camera();
  cam.T_B_C = mount.T_B_C();
  cam.time_offset_s = 0.004;  // t_imu = t_cam + 4 ms
  rig.cameras = {cam};
  FrontendConfig config;
  config.max_features = 30;
  config.min_distance_px = 10;
  ImageFeatureSource source(rig, config, "", [](RgbdFrame& f) { f.intensity = texture_frame(static_cast<int>(f.index)); });

  const auto imu_time = [](Timestamp t) { return 1e-9 * static_cast<double>(t - 1'000'000'000); };
  constexpr Timestamp kImuStep = 5'000'000;
  Timestamp next_imu = 0;
  double worst = 0;
  for (std::uint64_t k = 0; k < 20; ++k) {
    const RgbdFrame frame = frame_at(k);
    const Timestamp t_imu = frame.t + seconds_to_ns(cam.time_offset_s);
    for (; next_imu <= t_imu + kImuStep; next_imu += kImuStep)  // as the event stream delivers them
      source.add_imu(gyro_sample(1'000'000'000 + next_imu, trajectory.state(1e-9 * next_imu).omega_B));
    ASSERT_TRUE(source.track(frame));
    if (k == 0) {
      EXPECT_FALSE(source.last_rotation());
      continue;
    }
    ASSERT_TRUE(source.last_rotation());
    const Timestamp t_prev = frame_at(k - 1).t + seconds_to_ns(cam.time_offset_s);
    const Mat3 R_W_Cp = (trajectory.state(imu_time(t_prev)).T_W_B * cam.T_B_C).rotation();
    const Mat3 R_W_Cc = (trajectory.state(imu_time(t_imu)).T_W_B * cam.T_B_C).rotation();
    const Mat3 R_cur_prev = R_W_Cc.transpose() * R_W_Cp;
    EXPECT_GT(angle_between(R_cur_prev, Mat3::Identity()), 1e-3) << "frame " << k << ": the test needs rotation";
    worst = std::max(worst, angle_between(*source.last_rotation(), R_cur_prev));
  }
  // Linear interpolation of a smooth rate at 200 Hz: errors of order |alpha'| dt^2 T, micro-radians.
  EXPECT_LT(worst, 2e-5);
}

}  // namespace
}  // namespace navaid::estimation
