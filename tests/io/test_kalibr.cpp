#include <gtest/gtest.h>

#include "fixtures/euroc_fixture.hpp"
#include "fixtures/fixture_util.hpp"
#include "fixtures/kalibr_fixture.hpp"
#include "navaid/io/euroc.hpp"
#include "navaid/io/kalibr.hpp"
#include "test_support.hpp"

namespace navaid::io {
namespace {

namespace fs = std::filesystem;
using testing::ScratchDir;
using testing::write_text;
using testing::datasets::expect_config_error;
using testing::datasets::expect_io_error;
using testing::datasets::replace_text;

class KalibrCamchain : public ::testing::Test {
 protected:
  void SetUp() override { write_text(file_, testing::datasets::kKalibrCamchainImucam); }
  void expect_error(const std::string& key, std::initializer_list<std::string> fragments = {}) {
    expect_config_error([&] { read_kalibr_camchain(file_); }, "camchain-imucam.yaml", key, fragments);
  }
  ScratchDir dir_{"kalibr-camchain"};
  fs::path file_ = dir_ / "camchain-imucam.yaml";
};

TEST_F(KalibrCamchain, ReadsStereoChain) {
  const RigCalibration rig = read_kalibr_camchain(file_);
  ASSERT_EQ(rig.cameras.size(), 2u);
  EXPECT_FALSE(rig.imu.has_value());
  const CameraCalibration& c0 = rig.cameras[0];
  EXPECT_EQ(c0.name, "cam0");
  EXPECT_EQ(c0.width, 752);
  EXPECT_EQ(c0.height, 480);
  EXPECT_DOUBLE_EQ(c0.fx, 458.654);
  EXPECT_DOUBLE_EQ(c0.fy, 457.296);
  EXPECT_DOUBLE_EQ(c0.cx, 367.215);
  EXPECT_DOUBLE_EQ(c0.cy, 248.375);
  EXPECT_EQ(c0.distortion, DistortionModel::kRadialTangential);
  EXPECT_EQ(c0.distortion_coeffs, (std::vector<double>{-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05}));
  EXPECT_EQ(c0.time_offset_s, 0.0);
  // T_B_C is the inverse of T_cam_imu: its translation is EuRoC's T_BS translation.
  EXPECT_NEAR(c0.T_B_C.t.x(), -0.0216401454975, 1e-10);
  EXPECT_NEAR(c0.T_B_C.t.y(), -0.064676986768, 1e-10);
  EXPECT_NEAR(c0.T_B_C.t.z(), 0.00981073058949, 1e-10);
  EXPECT_EQ(rig.cameras[1].name, "cam1");
  EXPECT_DOUBLE_EQ(rig.cameras[1].cx, 379.999);
  // Stereo baseline from the two extrinsics: 0.110 m along cam1's x.
  const SE3 T_C1_C0 = rig.cameras[1].T_B_C.inverse() * c0.T_B_C;
  EXPECT_NEAR(T_C1_C0.t.x(), -0.110073808127, 1e-9);
}

TEST_F(KalibrCamchain, AgreesWithEurocSensorYaml) {
  write_text(dir_ / "sensor.yaml", testing::datasets::kEurocCam0Yaml);
  const CameraCalibration euroc = read_euroc_camera_yaml(dir_ / "sensor.yaml", "cam0");
  const CameraCalibration kalibr = read_kalibr_camchain(file_).cameras[0];
  EXPECT_TRUE(euroc.T_B_C.is_approx(kalibr.T_B_C, 1e-9));
  EXPECT_EQ(euroc.distortion_coeffs, kalibr.distortion_coeffs);
}

TEST_F(KalibrCamchain, TimeshiftEquidistantAndNone) {
  replace_text(file_, "timeshift_cam_imu: 0.0", "timeshift_cam_imu: -0.0123");
  replace_text(file_, "distortion_model: radtan", "distortion_model: equidistant");
  replace_text(file_, "distortion_model: radtan", "distortion_model: none");
  replace_text(file_, "[-0.28368365, 0.07451284, -0.00010473, -3.5559070e-05]", "[]");
  const RigCalibration rig = read_kalibr_camchain(file_);
  EXPECT_DOUBLE_EQ(rig.cameras[0].time_offset_s, -0.0123);
  EXPECT_EQ(rig.cameras[0].distortion, DistortionModel::kEquidistant);
  EXPECT_EQ(rig.cameras[1].distortion, DistortionModel::kNone);
  EXPECT_TRUE(rig.cameras[1].distortion_coeffs.empty());
}

TEST_F(KalibrCamchain, MissingTimeshiftMeansZero) {
  replace_text(file_, "  timeshift_cam_imu: 0.0\ncam1:", "cam1:");
  EXPECT_EQ(read_kalibr_camchain(file_).cameras[0].time_offset_s, 0.0);
}

TEST_F(KalibrCamchain, MissingKey) {
  replace_text(file_, "  intrinsics: [458.654, 457.296, 367.215, 248.375]\n", "");
  expect_error("cam0.intrinsics", {"missing"});
}

TEST_F(KalibrCamchain, MissingExtrinsics) {
  replace_text(file_, "  T_cam_imu:\n  - [0.0125552670891", "  T_imu_cam:\n  - [0.0125552670891");
  expect_error("cam1.T_cam_imu", {"missing"});
}

TEST_F(KalibrCamchain, WrongType) {
  replace_text(file_, "[458.654, 457.296, 367.215, 248.375]", "[458.654, fv, 367.215, 248.375]");
  expect_error("cam0.intrinsics[1]", {"expected a number, found 'fv'"});
}

TEST_F(KalibrCamchain, WrongTypeScalarInsteadOfList) {
  replace_text(file_, "resolution: [752, 480]", "resolution: 752x480");
  expect_error("cam0.resolution", {"expected [width, height]"});
}

TEST_F(KalibrCamchain, WrongIntrinsicsCount) {
  replace_text(file_, "[458.654, 457.296, 367.215, 248.375]", "[458.654, 457.296, 367.215]");
  expect_error("cam0.intrinsics", {"expected 4 values, found 3"});
}

TEST_F(KalibrCamchain, MatrixWithThreeRows) {
  replace_text(file_, "  - [0.00414029679422, 0.025715529948, 0.999660727178, -0.00805460246003]\n", "");
  expect_error("cam0.T_cam_imu", {"4x4", "found 3 rows"});
}

TEST_F(KalibrCamchain, MatrixRowTooShort) {
  replace_text(file_, "[0.00414029679422, 0.025715529948, 0.999660727178, -0.00805460246003]",
               "[0.00414029679422, 0.025715529948, 0.999660727178]");
  expect_error("cam0.T_cam_imu[2]", {"found 3 values"});
}

TEST_F(KalibrCamchain, NonRigidRotation) {
  // Scaled by 1.01 in the first row: |R^T R - I| ~ 2e-2.
  replace_text(file_, "[0.0148655429818, 0.999557249008, -0.0257744366974,",
               "[0.0150142, 1.0095528, -0.0260321,");
  expect_error("cam0.T_cam_imu", {"not orthonormal", "allowed <= 1e-6"});
}

TEST_F(KalibrCamchain, RotationJustOutsideTolerance) {
  // 1e-5 relative error in one entry is beyond 1e-6.
  replace_text(file_, "0.999660727178, -0.00805460246003", "0.999670727178, -0.00805460246003");
  expect_error("cam0.T_cam_imu", {"not orthonormal"});
}

TEST_F(KalibrCamchain, Reflection) {
  replace_text(file_, "[0.00414029679422, 0.025715529948, 0.999660727178,",
               "[-0.00414029679422, -0.025715529948, -0.999660727178,");
  expect_error("cam0.T_cam_imu", {"reflection"});
}

TEST_F(KalibrCamchain, BadBottomRow) {
  replace_text(file_, "  - [0.0, 0.0, 0.0, 1.0]\n  cam_overlaps: [1]", "  - [0.0, 0.0, 1.0, 1.0]\n  cam_overlaps: [1]");
  expect_error("cam0.T_cam_imu", {"bottom row"});
}

TEST_F(KalibrCamchain, UnsupportedModels) {
  replace_text(file_, "distortion_model: radtan", "distortion_model: fov");
  expect_error("cam0.distortion_model", {"unsupported distortion model 'fov'"});
  write_text(file_, testing::datasets::kKalibrCamchainImucam);
  replace_text(file_, "camera_model: pinhole", "camera_model: omni");
  expect_error("cam0.camera_model", {"unsupported camera model 'omni'"});
}

TEST_F(KalibrCamchain, DistortionCoefficientCount) {
  replace_text(file_, "distortion_model: radtan", "distortion_model: equidistant");
  replace_text(file_, "[-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]", "[-0.28340811, 0.07395907]");
  expect_error("cam0.distortion_coeffs", {"equidistant needs 4 coefficients"});
}

TEST_F(KalibrCamchain, NonPositiveFocalLengthAndResolution) {
  replace_text(file_, "[458.654, 457.296,", "[-458.654, 457.296,");
  expect_error("cam0.intrinsics", {"must be > 0"});
  write_text(file_, testing::datasets::kKalibrCamchainImucam);
  replace_text(file_, "resolution: [752, 480]", "resolution: [752, 0]");
  expect_error("cam0.resolution", {"must be > 0"});
}

TEST_F(KalibrCamchain, NonFiniteValue) {
  replace_text(file_, "timeshift_cam_imu: 0.0", "timeshift_cam_imu: .nan");
  expect_error("cam0.timeshift_cam_imu", {"finite"});
}

TEST_F(KalibrCamchain, CamerasMustStartAtCam0AndBeConsecutive) {
  replace_text(file_, "cam1:", "cam2:");
  expect_error("cam1", {"consecutively"});
  write_text(file_, "imu0: {}\n");
  expect_error("cam0", {"missing"});
}

TEST_F(KalibrCamchain, SyntaxErrorNamesLine) {
  replace_text(file_, "resolution: [752, 480]", "resolution: [752, 480");
  expect_io_error([&] { read_kalibr_camchain(file_); }, "camchain-imucam.yaml", 0, {"YAML syntax error"});
  const auto e = testing::expect_throw<IoError>([&] { read_kalibr_camchain(file_); });
  ASSERT_TRUE(e.has_value());
  EXPECT_GT(e->line(), 0u);
}

TEST_F(KalibrCamchain, MissingFile) {
  expect_io_error([&] { read_kalibr_camchain(dir_ / "absent.yaml"); }, "absent.yaml", 0, {"does not exist"});
}

class KalibrImu : public ::testing::Test {
 protected:
  void SetUp() override { write_text(file_, testing::datasets::kKalibrImuChain); }
  ScratchDir dir_{"kalibr-imu"};
  fs::path file_ = dir_ / "imu.yaml";
};

TEST_F(KalibrImu, ReadsOutputForm) {
  const ImuCalibration imu = read_kalibr_imu(file_);
  EXPECT_DOUBLE_EQ(imu.accel_noise_density, 0.002);
  EXPECT_DOUBLE_EQ(imu.accel_random_walk, 0.003);
  EXPECT_DOUBLE_EQ(imu.gyro_noise_density, 0.00016968);
  EXPECT_DOUBLE_EQ(imu.gyro_random_walk, 1.9393e-05);
  EXPECT_DOUBLE_EQ(imu.rate_hz, 200.0);
  EXPECT_TRUE(imu.T_B_I.is_approx(SE3::identity(), 0.0));
}

TEST_F(KalibrImu, TibIsInverted) {
  replace_text(file_, "- [1.0, 0.0, 0.0, 0.0]\n  - [0.0, 1.0, 0.0, 0.0]\n  - [0.0, 0.0, 1.0, 0.0]",
               "- [0.0, -1.0, 0.0, 0.1]\n  - [1.0, 0.0, 0.0, 0.0]\n  - [0.0, 0.0, 1.0, 0.0]");
  const ImuCalibration imu = read_kalibr_imu(file_);
  // T_i_b maps b into i; T_B_I = T_i_b^-1 maps the IMU origin to T_i_b^-1 * 0.
  const SE3 T_i_b(Quat(Eigen::AngleAxisd(EIGEN_PI / 2, Vec3::UnitZ())), Vec3(0.1, 0, 0));
  EXPECT_TRUE(imu.T_B_I.is_approx(T_i_b.inverse(), 1e-12));
}

TEST_F(KalibrImu, ReadsFlatInputForm) {
  write_text(file_, testing::datasets::kKalibrImuFlat);
  const ImuCalibration imu = read_kalibr_imu(file_);
  EXPECT_DOUBLE_EQ(imu.accel_noise_density, 1.86e-03);
  EXPECT_DOUBLE_EQ(imu.gyro_random_walk, 2.66e-05);
  EXPECT_DOUBLE_EQ(imu.rate_hz, 200.0);
}

TEST_F(KalibrImu, NegativeNoise) {
  replace_text(file_, "gyroscope_noise_density: 0.00016968", "gyroscope_noise_density: -0.00016968");
  expect_config_error([&] { read_kalibr_imu(file_); }, "imu.yaml", "imu0.gyroscope_noise_density",
                      {"must be > 0", "-0.00016968"});
}

TEST_F(KalibrImu, NegativeRandomWalkAndZeroRate) {
  replace_text(file_, "accelerometer_random_walk: 0.003", "accelerometer_random_walk: -1e-4");
  expect_config_error([&] { read_kalibr_imu(file_); }, "imu.yaml", "imu0.accelerometer_random_walk", {">= 0"});
  write_text(file_, testing::datasets::kKalibrImuChain);
  replace_text(file_, "update_rate: 200.0", "update_rate: 0");
  expect_config_error([&] { read_kalibr_imu(file_); }, "imu.yaml", "imu0.update_rate", {"must be > 0"});
}

TEST_F(KalibrImu, MissingKeyAndWrongType) {
  replace_text(file_, "  gyroscope_random_walk: 1.9393e-05\n", "");
  expect_config_error([&] { read_kalibr_imu(file_); }, "imu.yaml", "imu0.gyroscope_random_walk", {"missing"});
  write_text(file_, testing::datasets::kKalibrImuFlat);
  replace_text(file_, "1.86e-03", "[1.86e-03]");
  expect_config_error([&] { read_kalibr_imu(file_); }, "imu.yaml", "accelerometer_noise_density",
                      {"expected a number, found a sequence"});
}

TEST_F(KalibrImu, BadTib) {
  replace_text(file_, "- [0.0, 0.0, 1.0, 0.0]", "- [0.0, 0.0, 2.0, 0.0]");
  expect_config_error([&] { read_kalibr_imu(file_); }, "imu.yaml", "imu0.T_i_b", {"not orthonormal"});
}

}  // namespace
}  // namespace navaid::io
