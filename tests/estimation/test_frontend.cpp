// Front-end building blocks with known answers: config validation, patch depth association,
// keyframe decision.
#include <gtest/gtest.h>

#include <cmath>

#include "navaid/core/camera.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/estimation/frontend/depth_association.hpp"
#include "navaid/estimation/frontend/feature_tracker.hpp"
#include "navaid/estimation/frontend/frontend_config.hpp"
#include "navaid/estimation/frontend/keyframe_selector.hpp"
#include "test_support.hpp"

namespace navaid::estimation {
namespace {

CameraCalibration pinhole(int w = 640, int h = 480, double f = 460.0) {
  CameraCalibration c;
  c.width = w;
  c.height = h;
  c.fx = c.fy = f;
  c.cx = (w - 1) / 2.0;
  c.cy = (h - 1) / 2.0;
  c.depth_min_m = 0.3;
  c.depth_max_m = 5.0;
  return c;
}

TEST(FrontendConfig, DefaultsAreValidAndBadValuesNameTheirKey) {
  EXPECT_NO_THROW(validate(FrontendConfig{}));
  const auto expect_key = [](const char* key, auto edit) {
    FrontendConfig c;
    edit(c);
    const auto e = navaid::testing::expect_throw<ConfigError>([&] { validate(c, "test.yaml"); }, key);
    ASSERT_TRUE(e.has_value());
    EXPECT_EQ(e->key(), key);
    EXPECT_EQ(e->file(), "test.yaml");
  };
  expect_key("max_features", [](FrontendConfig& c) { c.max_features = 0; });
  expect_key("detect_min_missing", [](FrontendConfig& c) { c.detect_min_missing = 151; });
  expect_key("min_distance_px", [](FrontendConfig& c) { c.min_distance_px = -1; });
  expect_key("quality_level", [](FrontendConfig& c) { c.quality_level = 1.0; });
  expect_key("corner_block_size", [](FrontendConfig& c) { c.corner_block_size = 4; });
  expect_key("depth_edge_margin_px", [](FrontendConfig& c) { c.depth_edge_margin_px = -1; });
  expect_key("depth_edge_relative_jump", [](FrontendConfig& c) { c.depth_edge_relative_jump = 0; });
  expect_key("klt_window_px", [](FrontendConfig& c) { c.klt_window_px = 20; });
  expect_key("klt_max_level", [](FrontendConfig& c) { c.klt_max_level = 9; });
  expect_key("klt_max_iterations", [](FrontendConfig& c) { c.klt_max_iterations = 0; });
  expect_key("klt_epsilon", [](FrontendConfig& c) { c.klt_epsilon = 0; });
  expect_key("fb_threshold_px", [](FrontendConfig& c) { c.fb_threshold_px = std::nan(""); });
  expect_key("fb_max_level", [](FrontendConfig& c) { c.fb_max_level = -1; });
  expect_key("klt_threads", [](FrontendConfig& c) { c.klt_threads = 0; });
  expect_key("klt_threads", [](FrontendConfig& c) { c.klt_threads = 17; });
  expect_key("drift_check_interval", [](FrontendConfig& c) { c.drift_check_interval = -1; });
  expect_key("drift_max_px", [](FrontendConfig& c) { c.drift_max_px = 0; });
  expect_key("ransac_threshold_px", [](FrontendConfig& c) { c.ransac_threshold_px = 0; });
  expect_key("ransac_confidence", [](FrontendConfig& c) { c.ransac_confidence = 1.0; });
  expect_key("border_px", [](FrontendConfig& c) { c.border_px = -0.5; });
  expect_key("depth_patch_size", [](FrontendConfig& c) { c.depth_patch_size = 4; });
  expect_key("depth_max_relative_spread", [](FrontendConfig& c) { c.depth_max_relative_spread = 0; });
  expect_key("depth_min_valid", [](FrontendConfig& c) { c.depth_min_valid = 10; });
  expect_key("keyframe_parallax_px", [](FrontendConfig& c) { c.keyframe_parallax_px = -10; });
  expect_key("keyframe_min_tracked", [](FrontendConfig& c) { c.keyframe_min_tracked = -1; });
  // The tracker validates on construction.
  FrontendConfig bad;
  bad.klt_window_px = 3;
  EXPECT_THROW(FeatureTracker(make_camera_model(pinhole()), bad), ConfigError);
}

TEST(FeatureTracker, RejectsFramesThatDoNotFitTheCamera) {
  FeatureTracker tracker(make_camera_model(pinhole(64, 48, 50.0)));
  RgbdFrame frame;
  EXPECT_THROW(tracker.track(frame), Error);  // no intensity loaded
  frame.intensity = ImageU8(32, 24);
  EXPECT_THROW(tracker.track(frame), Error);  // wrong size
  frame.intensity = ImageU8(64, 48, 2);
  EXPECT_THROW(tracker.track(frame), Error);  // two channels
  frame.intensity = ImageU8(64, 48);
  frame.depth = ImageF32(10, 10);
  EXPECT_THROW(tracker.track(frame), Error);  // depth of another size
  frame.depth = ImageF32(64, 48);
  EXPECT_TRUE(tracker.track(frame).features.empty());  // a flat image has no corners
}

DepthPatchOptions patch_options(int size = 3) {
  DepthPatchOptions o;
  o.patch_size = size;
  o.min_valid = size == 3 ? 5 : 13;
  o.max_relative_spread = 0.1;
  o.min_depth_m = 0.3;
  o.max_depth_m = 5.0;
  return o;
}

TEST(DepthAssociation, MedianOfValidPatchDepths) {
  ImageF32 d(20, 20, 1, 2.0f);
  // 3x3 around (10, 10): values 1.95 .. 2.05 plus two holes; median of the seven valid ones.
  const float v[9] = {1.95f, 2.05f, 0.0f, 2.01f, 1.99f, 0.0f, 2.02f, 1.97f, 2.0f};
  for (int k = 0; k < 9; ++k) d.at(9 + k % 3, 9 + k / 3) = v[k];
  const auto z = associate_depth(d, Eigen::Vector2d(10.3, 9.6), patch_options());  // nearest pixel (10, 10)
  ASSERT_TRUE(z.has_value());
  EXPECT_NEAR(*z, 2.0, 1e-6);  // sorted: 1.95 1.97 1.99 2.00 2.01 2.02 2.05
  // Even count: the mean of the middle pair.
  d.at(11, 11) = 0.0f;  // removes 2.0
  const auto z6 = associate_depth(d, Eigen::Vector2d(10, 10), patch_options());
  ASSERT_TRUE(z6.has_value());
  EXPECT_NEAR(*z6, 0.5 * (1.99 + 2.01), 1e-6);
}

TEST(DepthAssociation, RefusesEdgesHolesRangeAndOutside) {
  ImageF32 d(20, 20, 1, 2.0f);
  for (int y = 0; y < 20; ++y)
    for (int x = 11; x < 20; ++x) d.at(x, y) = 4.0f;  // depth edge between columns 10 and 11
  EXPECT_FALSE(associate_depth(d, Eigen::Vector2d(10, 10), patch_options()).has_value());
  EXPECT_NEAR(*associate_depth(d, Eigen::Vector2d(9, 10), patch_options()), 2.0, 1e-6);
  EXPECT_NEAR(*associate_depth(d, Eigen::Vector2d(12, 10), patch_options()), 4.0, 1e-6);
  EXPECT_FALSE(associate_depth(d, Eigen::Vector2d(9, 10), patch_options(5)).has_value());  // 5x5 reaches the edge
  // Too few valid pixels: 4 of 9.
  ImageF32 holes(20, 20);
  for (int k = 0; k < 4; ++k) holes.at(4 + k % 3, 4 + k / 3) = 1.0f;
  EXPECT_FALSE(associate_depth(holes, Eigen::Vector2d(5, 5), patch_options()).has_value());
  holes.at(6, 5) = 1.0f;
  EXPECT_TRUE(associate_depth(holes, Eigen::Vector2d(5, 5), patch_options()).has_value());
  // Sensor range.
  ImageF32 far(20, 20, 1, 6.0f), near(20, 20, 1, 0.2f);
  EXPECT_FALSE(associate_depth(far, Eigen::Vector2d(5, 5), patch_options()).has_value());
  EXPECT_FALSE(associate_depth(near, Eigen::Vector2d(5, 5), patch_options()).has_value());
  // At the image corner only 4 pixels exist; outside entirely nothing.
  ImageF32 flat(20, 20, 1, 1.0f);
  EXPECT_FALSE(associate_depth(flat, Eigen::Vector2d(0, 0), patch_options()).has_value());
  EXPECT_FALSE(associate_depth(flat, Eigen::Vector2d(-5, 30), patch_options()).has_value());
  EXPECT_FALSE(associate_depth(flat, Eigen::Vector2d(std::nan(""), 3), patch_options()).has_value());
  EXPECT_FALSE(associate_depth(ImageF32{}, Eigen::Vector2d(3, 3), patch_options()).has_value());
}

FeatureFrame grid_frame(const Eigen::Vector2d& shift, std::uint64_t first_id = 0, int n = 60) {
  FeatureFrame f;
  for (int k = 0; k < n; ++k) {
    FeatureObservation o;
    o.track_id = first_id + static_cast<std::uint64_t>(k);
    o.uv = Eigen::Vector2d(100.0 + 40.0 * (k % 10), 100.0 + 40.0 * (k / 10)) + shift;
    f.features.push_back(o);
  }
  return f;
}

TEST(KeyframeSelector, AverageParallaxAndTrackCountKnownAnswers) {
  const auto cam = make_camera_model(pinhole());
  KeyframeCriteria c;  // 10 px, 50 tracks
  const FeatureFrame kf = grid_frame(Eigen::Vector2d::Zero());

  KeyframeDecision d = decide_keyframe(kf, grid_frame(Eigen::Vector2d(6, 8)), *cam, c);
  EXPECT_EQ(d.common_tracks, 60u);
  EXPECT_NEAR(d.average_parallax_px, 10.0, 1e-9);  // |(6, 8)| = 10: at the threshold
  EXPECT_TRUE(d.keyframe);
  d = decide_keyframe(kf, grid_frame(Eigen::Vector2d(6, 7.9)), *cam, c);
  EXPECT_NEAR(d.average_parallax_px, std::hypot(6.0, 7.9), 1e-9);
  EXPECT_FALSE(d.keyframe);

  // Half the features moved by 16 px, half stayed: average 8 px.
  FeatureFrame half = kf;
  for (std::size_t i = 0; i < half.features.size(); i += 2) half.features[i].uv.x() += 16.0;
  d = decide_keyframe(kf, half, *cam, c);
  EXPECT_NEAR(d.average_parallax_px, 8.0, 1e-9);
  EXPECT_FALSE(d.keyframe);

  // 11 tracks left (ids 49..59): too few tracked, even without motion.
  FeatureFrame few = kf;
  few.features.erase(few.features.begin(), few.features.begin() + 49);
  d = decide_keyframe(kf, few, *cam, c);
  EXPECT_EQ(d.common_tracks, 11u);
  EXPECT_NEAR(d.average_parallax_px, 0.0, 1e-12);
  EXPECT_TRUE(d.keyframe);
  c.min_tracked = 11;
  EXPECT_FALSE(decide_keyframe(kf, few, *cam, c).keyframe);
  // Nothing in common: keyframe with zero parallax.
  d = decide_keyframe(kf, grid_frame(Eigen::Vector2d::Zero(), 1000), *cam, c);
  EXPECT_EQ(d.common_tracks, 0u);
  EXPECT_TRUE(d.keyframe);
}

TEST(KeyframeSelector, RotationCompensationRemovesPureRotationParallax) {
  CameraCalibration calib = pinhole();
  calib.distortion = DistortionModel::kRadialTangential;
  calib.distortion_coeffs = {-0.2, 0.05, 0.001, -0.001};
  const auto cam = make_camera_model(calib);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.05, Eigen::Vector3d(0.2, 1.0, 0.1).normalized()).toRotationMatrix();
  const FeatureFrame kf = grid_frame(Eigen::Vector2d::Zero());
  FeatureFrame cur = kf;
  for (auto& o : cur.features) o.uv = *cam->project(R * *cam->unproject(o.uv));
  const KeyframeCriteria c;
  const KeyframeDecision plain = decide_keyframe(kf, cur, *cam, c);
  EXPECT_GT(plain.average_parallax_px, 20.0);  // ~ f * 0.05 rad
  EXPECT_TRUE(plain.keyframe);
  const KeyframeDecision compensated = decide_keyframe(kf, cur, *cam, c, R);
  EXPECT_LT(compensated.average_parallax_px, 1e-6);
  EXPECT_FALSE(compensated.keyframe);
  // The tracker's helper uses its config's thresholds.
  FrontendConfig fc;
  fc.keyframe_parallax_px = 1000.0;
  fc.keyframe_min_tracked = 10;
  EXPECT_FALSE(FeatureTracker(make_camera_model(calib), fc).decide_keyframe(kf, cur).keyframe);
}

TEST(KeyframeSelector, UnsortedIdsAreRejected) {
  const auto cam = make_camera_model(pinhole());
  FeatureFrame bad = grid_frame(Eigen::Vector2d::Zero());
  std::swap(bad.features[3], bad.features[4]);
  EXPECT_THROW(decide_keyframe(grid_frame(Eigen::Vector2d::Zero()), bad, *cam, KeyframeCriteria{}), std::invalid_argument);
}

}  // namespace
}  // namespace navaid::estimation
