#include <gtest/gtest.h>

#include "fixtures/fixture_util.hpp"
#include "fixtures/tum_rgbd_fixture.hpp"
#include "navaid/io/tum_rgbd.hpp"
#include "test_support.hpp"

namespace navaid::io {
namespace {

namespace fs = std::filesystem;
using testing::ScratchDir;
using testing::write_text;
using testing::datasets::expect_io_error;
using testing::datasets::kTumDepthTimes;
using testing::datasets::kTumRgbTimes;
using testing::datasets::replace_line;
using testing::datasets::TumOptions;
using testing::datasets::write_tum_sequence;

Timestamp seconds(const std::string& text) { return *parse_seconds(text); }

TEST(TumRgbd, ReadsSequence) {
  ScratchDir dir("tum-rgbd");
  const fs::path folder = write_tum_sequence(dir.path());
  const Recording rec = read_tum_rgbd(folder);
  EXPECT_EQ(rec.format, "tum-rgbd");

  // rgb 0,1,3,4 pair with depth 0,2,3,4 (see the fixture); frame time = rgb time.
  const std::vector<std::pair<int, int>> expected = {{0, 0}, {1, 2}, {3, 3}, {4, 4}};
  ASSERT_EQ(rec.frames.size(), expected.size());
  for (std::size_t k = 0; k < expected.size(); ++k) {
    const RgbdFrame& f = rec.frames[k];
    const auto& rgb = kTumRgbTimes[static_cast<std::size_t>(expected[k].first)];
    const auto& depth = kTumDepthTimes[static_cast<std::size_t>(expected[k].second)];
    EXPECT_EQ(f.t, seconds(rgb));
    EXPECT_EQ(f.index, k);
    EXPECT_EQ(f.camera, "cam0");
    EXPECT_EQ(fs::path(f.intensity_path), folder / "rgb" / (rgb + ".png"));
    EXPECT_EQ(fs::path(f.depth_path), folder / "depth" / (depth + ".png"));
    EXPECT_TRUE(f.has_depth());
    EXPECT_DOUBLE_EQ(f.depth_png_scale_m, 1.0 / 5000.0);
  }
  EXPECT_EQ(rec.frames[0].t, 1305031102175304000LL);

  // One colour and one depth image left over: counted warnings, not errors.
  EXPECT_EQ(rec.report.total(), 2u);
  ASSERT_EQ(rec.report.warnings.size(), 2u);
  EXPECT_NE(rec.report.warnings[0].source.find("rgb.txt"), std::string::npos);
  EXPECT_NE(rec.report.warnings[0].message.find("without a depth image within 0.02 s"), std::string::npos);
  EXPECT_NE(rec.report.warnings[1].source.find("depth.txt"), std::string::npos);

  ASSERT_EQ(rec.imu.size(), 3u);
  EXPECT_EQ(rec.imu[0].t, 1305031098621849000LL);
  EXPECT_FALSE(rec.imu[0].has_gyro);
  EXPECT_EQ(rec.imu[0].gyro, Vec3::Zero());
  EXPECT_DOUBLE_EQ(rec.imu[0].accel.y(), -8.629913);
  EXPECT_DOUBLE_EQ(rec.imu[2].accel.x(), -0.067726);

  ASSERT_EQ(rec.groundtruth.size(), 3u);
  EXPECT_EQ(rec.groundtruth[0].t, 1305031098665900000LL);
  EXPECT_DOUBLE_EQ(rec.groundtruth[0].T_W_B.t.z(), 1.6380);
  const Quat q = Quat(-0.3986, 0.6132, 0.5962, -0.3311).normalized();  // qw is last in the file
  EXPECT_LT(rec.groundtruth[0].T_W_B.q.angularDistance(q), 1e-12);

  ASSERT_EQ(rec.calibration.cameras.size(), 1u);
  const CameraCalibration& cam = rec.calibration.cameras[0];
  EXPECT_DOUBLE_EQ(cam.fx, 517.3);
  EXPECT_DOUBLE_EQ(cam.cy, 255.3);
  EXPECT_EQ(cam.width, 640);
  EXPECT_EQ(cam.height, 480);
  EXPECT_EQ(cam.distortion, DistortionModel::kRadialTangential);
  EXPECT_EQ(cam.distortion_coeffs, (std::vector<double>{0.2624, -0.9531, -0.0054, 0.0026, 1.1633}));
  EXPECT_FALSE(rec.calibration.imu.has_value());
}

TEST(TumRgbd, CameraFromFolderName) {
  EXPECT_EQ(tum_camera_from_name("rgbd_dataset_freiburg1_xyz"), TumCamera::kFreiburg1);
  EXPECT_EQ(tum_camera_from_name("rgbd_dataset_freiburg2_pioneer_360"), TumCamera::kFreiburg2);
  EXPECT_EQ(tum_camera_from_name("rgbd_dataset_freiburg3_long_office_household"), TumCamera::kFreiburg3);
  EXPECT_EQ(tum_camera_from_name("my_kinect_capture"), TumCamera::kRosDefault);
  const auto fr2 = tum_rgbd_camera(TumCamera::kFreiburg2);
  EXPECT_DOUBLE_EQ(fr2.fx, 520.9);
  EXPECT_DOUBLE_EQ(fr2.distortion_coeffs[4], 0.9172);
  const auto fr3 = tum_rgbd_camera(TumCamera::kFreiburg3);
  EXPECT_DOUBLE_EQ(fr3.fy, 539.2);
  EXPECT_EQ(fr3.distortion, DistortionModel::kNone);
  const auto ros = tum_rgbd_camera(TumCamera::kRosDefault);
  EXPECT_DOUBLE_EQ(ros.fx, 525.0);
  EXPECT_DOUBLE_EQ(ros.cx, 319.5);
  EXPECT_DOUBLE_EQ(ros.cy, 239.5);
}

TEST(TumRgbd, UnknownFolderNameUsesRosDefaultWithWarning) {
  ScratchDir dir("tum-rgbd-ros");
  TumOptions options;
  options.name = "kinect_capture";
  options.accelerometer = false;
  options.groundtruth = false;
  // A trailing separator must not hide the folder name.
  const Recording rec = read_tum_rgbd(write_tum_sequence(dir.path(), options).string() + "/");
  EXPECT_DOUBLE_EQ(rec.calibration.cameras[0].fx, 525.0);
  EXPECT_EQ(rec.report.total(), 3u);
  EXPECT_TRUE(rec.imu.empty());
  EXPECT_TRUE(rec.groundtruth.empty());
  EXPECT_EQ(rec.frames.size(), 4u);
}

TEST(TumRgbd, FolderNameWithTrailingSeparator) {
  ScratchDir dir("tum-rgbd-slash");
  TumOptions options;
  options.name = "rgbd_dataset_freiburg3_long_office_household";
  const Recording rec = read_tum_rgbd(write_tum_sequence(dir.path(), options).string() + "/");
  EXPECT_DOUBLE_EQ(rec.calibration.cameras[0].fx, 535.4);
  EXPECT_EQ(rec.report.total(), 2u);
}

TEST(TumRgbdAssociation, NearestOneToOneWithinTolerance) {
  const std::vector<Timestamp> rgb = {100, 200, 300, 400};
  const std::vector<Timestamp> depth = {95, 110, 290, 420, 500};
  const auto pairs = associate_nearest(rgb, depth, 20);
  // 100 takes 95 (5 < 10); 200 has nothing within 20; 300 takes 290; 400 - 420 is exactly 20: excluded.
  EXPECT_EQ(pairs, (std::vector<std::pair<std::size_t, std::size_t>>{{0, 0}, {2, 2}}));
}

TEST(TumRgbdAssociation, GreedyByDifferenceNotByOrder) {
  // 10 could take 18 (8) first in time order, but 20 - 18 = 2 is the better pair.
  const std::vector<Timestamp> rgb = {10, 20};
  const std::vector<Timestamp> depth = {3, 18};
  const auto pairs = associate_nearest(rgb, depth, 10);
  EXPECT_EQ(pairs, (std::vector<std::pair<std::size_t, std::size_t>>{{0, 0}, {1, 1}}));
  const auto single = associate_nearest({10, 20}, {18}, 10);
  EXPECT_EQ(single, (std::vector<std::pair<std::size_t, std::size_t>>{{1, 0}}));
  EXPECT_TRUE(associate_nearest({}, {1, 2}, 10).empty());
}

TEST(TumRgbdAssociation, ToleranceIsTwentyMilliseconds) {
  EXPECT_EQ(kTumAssociationTolerance, 20'000'000);
  const auto pairs = associate_nearest({1'000'000'000}, {1'019'999'999}, kTumAssociationTolerance);
  EXPECT_EQ(pairs.size(), 1u);
  EXPECT_TRUE(associate_nearest({1'000'000'000}, {1'020'000'000}, kTumAssociationTolerance).empty());
}

class TumRgbdCorrupt : public ::testing::Test {
 protected:
  void SetUp() override { folder_ = write_tum_sequence(dir_.path()); }
  void expect_error(const std::string& file, std::size_t line, std::initializer_list<std::string> fragments) {
    expect_io_error([&] { read_tum_rgbd(folder_); }, file, line, fragments);
  }
  ScratchDir dir_{"tum-rgbd-corrupt"};
  fs::path folder_;
};

TEST_F(TumRgbdCorrupt, TruncatedAccelerometerLine) {
  replace_line(folder_ / "accelerometer.txt", 5, "1305031098.631858 -0.029419 -8.629913");
  expect_error("accelerometer.txt", 5, {"expected 4 fields, found 3"});
}

TEST_F(TumRgbdCorrupt, NonNumericAndNonFinite) {
  replace_line(folder_ / "accelerometer.txt", 6, "1305031098.641862 -0.067726 -8.66822O -4.071957");
  expect_error("accelerometer.txt", 6, {"column 'ay'", "'-8.66822O' is not a number"});
  replace_line(folder_ / "accelerometer.txt", 6, "1305031098.641862 -0.067726 NaN -4.071957");
  expect_error("accelerometer.txt", 6, {"column 'ay'", "not a finite number"});
  replace_line(folder_ / "accelerometer.txt", 6, "1305031098.641862 -0.067726 -8.668220 -4.071957");
  replace_line(folder_ / "groundtruth.txt", 5, "1305031098.6758 1.3543 inf 1.6360 0.6129 0.5966 -0.3316 -0.3980");
  expect_error("groundtruth.txt", 5, {"column 'ty'", "not a finite number"});
}

TEST_F(TumRgbdCorrupt, DuplicateAndDecreasingTimestamps) {
  replace_line(folder_ / "rgb.txt", 6, "1305031102.211214 rgb/1305031102.243211.png");
  expect_error("rgb.txt", 6, {"duplicate timestamp 1305031102.211214000"});
  replace_line(folder_ / "rgb.txt", 6, "1305031102.243211 rgb/1305031102.243211.png");
  replace_line(folder_ / "depth.txt", 5, "1305031102.150000 depth/1305031102.194330.png");
  expect_error("depth.txt", 5, {"decreasing timestamp"});
}

TEST_F(TumRgbdCorrupt, MissingImageFile) {
  fs::remove(folder_ / "depth" / "1305031102.262886.png");
  expect_error("depth.txt", 7, {"image file 'depth/1305031102.262886.png' does not exist"});
}

TEST_F(TumRgbdCorrupt, BadGroundTruthQuaternion) {
  replace_line(folder_ / "groundtruth.txt", 6, "1305031098.6858 1.3524 0.6304 1.6345 0.6132 0.5976 -0.3313 -0.4970");
  expect_error("groundtruth.txt", 6, {"quaternion", "not within 1e-3 of 1"});
}

TEST_F(TumRgbdCorrupt, BadTimestampText) {
  replace_line(folder_ / "rgb.txt", 4, "1305031102,175304 rgb/1305031102.175304.png");
  expect_error("rgb.txt", 4, {"column 'timestamp'", "not a time in seconds"});
}

TEST_F(TumRgbdCorrupt, MissingListFile) {
  fs::remove(folder_ / "depth.txt");
  expect_error("depth.txt", 0, {"does not exist"});
  expect_io_error([&] { read_tum_rgbd(dir_ / "absent"); }, "absent", 0, {"is not a folder"});
}

}  // namespace
}  // namespace navaid::io
