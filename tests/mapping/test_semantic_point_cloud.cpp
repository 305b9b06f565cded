// eLabrador eq. (3) and (5): back-projection of depth pixels with their labels into W.
#include <gtest/gtest.h>

#include <cmath>

#include "navaid/core/camera.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/mapping/semantic_point_cloud.hpp"
#include "test_support.hpp"

namespace navaid::mapping {
namespace {

CameraCalibration test_camera() {
  CameraCalibration c;
  c.width = 640;
  c.height = 480;
  c.fx = 500;
  c.fy = 400;
  c.cx = 320;
  c.cy = 240;
  c.T_B_C = SE3(Quat(Eigen::AngleAxisd(-M_PI / 2, Vec3::UnitX())), Vec3(0.1, 0.0, 0.05));
  return c;
}

RgbdFrame frame_with_depth(float d) {
  RgbdFrame f;
  f.depth = ImageF32(640, 480, 1, d);
  return f;
}

SemanticPointCloudConfig every_pixel() {
  SemanticPointCloudConfig c;
  c.pixel_stride = 1;
  c.depth_min_m = 0.1;
  c.depth_max_m = 10.0;
  return c;
}

TEST(SemanticPointCloud, EquationThreeThenFive) {
  RgbdFrame f = frame_with_depth(0.0f);
  f.depth.at(420, 140) = 2.0f;
  const CameraCalibration cam = test_camera();
  const SE3 T_W_B(Quat(Eigen::AngleAxisd(0.3, Vec3::UnitZ())), Vec3(1.0, 2.0, 1.5));
  const auto cloud = make_semantic_point_cloud(f, cam, T_W_B, every_pixel());
  ASSERT_EQ(cloud.points.size(), 1u);
  // X = (u - cx) Z / fx = 100 * 2 / 500, Y = (v - cy) Z / fy = -100 * 2 / 400, Z = d.
  const Vec3 p_C(0.4, -0.5, 2.0);
  const Vec3 expected = T_W_B * (cam.T_B_C * p_C);
  EXPECT_NEAR((cloud.points[0].p_W.cast<double>() - expected).norm(), 0.0, 1e-5);
  EXPECT_NEAR((cloud.origin_W - (T_W_B * cam.T_B_C).t).norm(), 0.0, 1e-12);
  EXPECT_EQ(cloud.invalid_depth, 640u * 480u - 1u);
  EXPECT_FALSE(cloud.labelled);
  EXPECT_EQ(cloud.points[0].observation.semantic, SemanticClass::kUnlabeled);
}

TEST(SemanticPointCloud, StrideAndDepthRange) {
  RgbdFrame f = frame_with_depth(3.0f);
  f.depth.at(0, 0) = 0.2f;   // too near
  f.depth.at(4, 0) = 12.0f;  // too far
  SemanticPointCloudConfig c = every_pixel();
  c.pixel_stride = 4;
  c.depth_min_m = 0.3;
  c.depth_max_m = 6.0;
  const auto cloud = make_semantic_point_cloud(f, test_camera(), SE3(), c);
  EXPECT_EQ(cloud.points.size() + cloud.out_of_range, 160u * 120u);
  EXPECT_EQ(cloud.out_of_range, 2u);
}

TEST(SemanticPointCloud, LabelsConfidenceAndIgnoredClasses) {
  RgbdFrame f = frame_with_depth(2.0f);
  f.labels = ImageU8(640, 480, 1, static_cast<std::uint8_t>(SemanticClass::kSidewalk));
  f.label_confidence = ImageF32(640, 480, 1, 0.9f);
  f.labels->at(10, 10) = static_cast<std::uint8_t>(SemanticClass::kSky);
  f.labels->at(20, 10) = static_cast<std::uint8_t>(SemanticClass::kPerson);
  f.label_confidence->at(30, 10) = 0.25f;
  SemanticPointCloudConfig c = every_pixel();
  c.ignored_classes = {SemanticClass::kSky, SemanticClass::kPerson};
  const auto cloud = make_semantic_point_cloud(f, test_camera(), SE3(), c);
  EXPECT_TRUE(cloud.labelled);
  EXPECT_EQ(cloud.ignored_class, 2u);
  EXPECT_EQ(cloud.points.size(), 640u * 480u - 2u);
  // Row 10 holds pixel (30, 10) at index 10 * 640 + 30 - 2 (two points dropped before it).
  const auto& p = cloud.points[10 * 640 + 30 - 2];
  EXPECT_EQ(p.observation.semantic, SemanticClass::kSidewalk);
  EXPECT_FLOAT_EQ(p.observation.probability, 0.25f);
  EXPECT_FLOAT_EQ(cloud.points[0].observation.probability, 0.9f);
}

TEST(SemanticPointCloud, LabelsWithoutConfidenceTakeTheDefault) {
  RgbdFrame f = frame_with_depth(2.0f);
  f.labels = ImageU8(640, 480, 1, static_cast<std::uint8_t>(SemanticClass::kWall));
  SemanticPointCloudConfig c = every_pixel();
  c.default_label_probability = 0.65;
  const auto cloud = make_semantic_point_cloud(f, test_camera(), SE3(), c);
  EXPECT_FLOAT_EQ(cloud.points.front().observation.probability, 0.65f);
}

TEST(SemanticPointCloud, DistortedLensUsesTheUndistortedBearing) {
  CameraCalibration cam = test_camera();
  cam.distortion = DistortionModel::kRadialTangential;
  cam.distortion_coeffs = {-0.2, 0.05, 0.001, -0.001};
  RgbdFrame f = frame_with_depth(0.0f);
  f.depth.at(600, 60) = 2.5f;
  const auto cloud = make_semantic_point_cloud(f, cam, SE3(), every_pixel());
  ASSERT_EQ(cloud.points.size(), 1u);
  const Vec3 p_C = cam.T_B_C.inverse() * cloud.points[0].p_W.cast<double>();
  EXPECT_NEAR(p_C.z(), 2.5, 1e-5);
  const auto pixel = make_camera_model(cam)->project(p_C);
  ASSERT_TRUE(pixel);
  EXPECT_NEAR((*pixel - Eigen::Vector2d(600, 60)).norm(), 0.0, 1e-3);
}

TEST(SemanticPointCloud, BadInputsAreClearErrors) {
  const CameraCalibration cam = test_camera();
  RgbdFrame none;
  EXPECT_NE(navaid::testing::error_message<Error>([&] { make_semantic_point_cloud(none, cam, SE3(), every_pixel()); })
                .find("no depth"),
            std::string::npos);
  RgbdFrame small;
  small.depth = ImageF32(320, 240, 1, 1.0f);
  EXPECT_NE(navaid::testing::error_message<Error>([&] { make_semantic_point_cloud(small, cam, SE3(), every_pixel()); })
                .find("320x240"),
            std::string::npos);
  RgbdFrame labels = frame_with_depth(1.0f);
  labels.labels = ImageU8(640, 480, 1, 200);
  EXPECT_NE(navaid::testing::error_message<Error>([&] { make_semantic_point_cloud(labels, cam, SE3(), every_pixel()); })
                .find("not a class id"),
            std::string::npos);
  RgbdFrame mismatched = frame_with_depth(1.0f);
  mismatched.labels = ImageU8(640, 240, 1, 1);
  EXPECT_NE(navaid::testing::error_message<Error>([&] { make_semantic_point_cloud(mismatched, cam, SE3(), every_pixel()); })
                .find("label image"),
            std::string::npos);
}

TEST(SemanticPointCloud, ConfigKeys) {
  const Config c = Config::parse("mapping: {cloud: {pixel_stride: 2, ignored_classes: [sky, person]}}");
  const auto cfg = read_semantic_point_cloud_config(c);
  EXPECT_EQ(cfg.pixel_stride, 2);
  ASSERT_EQ(cfg.ignored_classes.size(), 2u);
  EXPECT_EQ(cfg.ignored_classes[1], SemanticClass::kPerson);
  const Config bad = Config::parse("mapping: {cloud: {ignored_classes: [skyy]}}");
  EXPECT_NE(navaid::testing::error_message<Error>([&] { read_semantic_point_cloud_config(bad); }).find("mapping.cloud.ignored_classes"),
            std::string::npos);
  const Config inverted = Config::parse("mapping: {cloud: {depth_min_m: 3, depth_max_m: 2}}");
  EXPECT_THROW(read_semantic_point_cloud_config(inverted), ConfigError);
}

}  // namespace
}  // namespace navaid::mapping
