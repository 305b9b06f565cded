#include <gtest/gtest.h>

#include "fixtures/euroc_fixture.hpp"
#include "fixtures/fixture_util.hpp"
#include "navaid/io/euroc.hpp"
#include "test_support.hpp"

namespace navaid::io {
namespace {

namespace fs = std::filesystem;
using testing::ScratchDir;
using testing::write_text;
using testing::datasets::EurocFixture;
using testing::datasets::EurocOptions;
using testing::datasets::expect_config_error;
using testing::datasets::expect_io_error;
using testing::datasets::line_of;
using testing::datasets::replace_line;
using testing::datasets::replace_text;
using testing::datasets::write_euroc_sequence;

TEST(Euroc, ReadsMonocularSequence) {
  ScratchDir dir("euroc-mono");
  const EurocFixture fx = write_euroc_sequence(dir / "MH_01_easy");
  const Recording rec = read_euroc(fx.sequence);
  EXPECT_EQ(rec.format, "euroc");
  EXPECT_EQ(rec.path, fx.sequence.string());
  EXPECT_EQ(rec.report.total(), 0u);

  ASSERT_EQ(rec.imu.size(), fx.imu_t.size());
  EXPECT_EQ(rec.imu.front().t, 1403636579758555392LL);
  EXPECT_EQ(rec.imu.back().t, fx.imu_t.back());
  EXPECT_TRUE(rec.imu.front().has_gyro);
  EXPECT_DOUBLE_EQ(rec.imu.front().gyro.x(), -0.099134701513277898);
  EXPECT_DOUBLE_EQ(rec.imu.front().gyro.z(), 0.028902652380957901);
  EXPECT_DOUBLE_EQ(rec.imu.front().accel.x(), 8.1476917083333333);
  EXPECT_DOUBLE_EQ(rec.imu.front().accel.z(), -2.4026292499999999);

  ASSERT_EQ(rec.frames.size(), 3u);
  for (std::size_t k = 0; k < rec.frames.size(); ++k) {
    const RgbdFrame& f = rec.frames[k];
    EXPECT_EQ(f.t, fx.cam_t[k]);
    EXPECT_EQ(f.index, k);
    EXPECT_EQ(f.camera, "cam0");
    EXPECT_FALSE(f.has_depth());
    EXPECT_TRUE(f.intensity.empty());  // lazy
    EXPECT_EQ(fs::path(f.intensity_path), fx.mav0 / "cam0" / "data" / (std::to_string(fx.cam_t[k]) + ".png"));
    EXPECT_TRUE(fs::exists(f.intensity_path));
  }

  ASSERT_EQ(rec.calibration.cameras.size(), 1u);
  const CameraCalibration& cam = rec.calibration.cameras[0];
  EXPECT_EQ(cam.name, "cam0");
  EXPECT_EQ(cam.width, 752);
  EXPECT_EQ(cam.height, 480);
  EXPECT_DOUBLE_EQ(cam.fx, 458.654);
  EXPECT_DOUBLE_EQ(cam.cy, 248.375);
  EXPECT_DOUBLE_EQ(cam.rate_hz, 20.0);
  EXPECT_EQ(cam.distortion, DistortionModel::kRadialTangential);
  EXPECT_EQ(cam.distortion_coeffs.size(), 4u);
  EXPECT_DOUBLE_EQ(cam.T_B_C.t.x(), -0.0216401454975);
  EXPECT_DOUBLE_EQ(cam.T_B_C.t.y(), -0.064676986768);
  EXPECT_NEAR(cam.T_B_C.rotation()(0, 1), -0.999880929698, 1e-9);

  ASSERT_TRUE(rec.calibration.imu.has_value());
  EXPECT_DOUBLE_EQ(rec.calibration.imu->gyro_noise_density, 1.6968e-04);
  EXPECT_DOUBLE_EQ(rec.calibration.imu->gyro_random_walk, 1.9393e-05);
  EXPECT_DOUBLE_EQ(rec.calibration.imu->accel_noise_density, 2.0e-3);
  EXPECT_DOUBLE_EQ(rec.calibration.imu->accel_random_walk, 3.0e-3);
  EXPECT_DOUBLE_EQ(rec.calibration.imu->rate_hz, 200.0);

  ASSERT_EQ(rec.groundtruth.size(), fx.gt_t.size());
  const GroundTruthState& gt = rec.groundtruth.front();
  EXPECT_EQ(gt.t, 1403636580838555648LL);
  EXPECT_DOUBLE_EQ(gt.T_W_B.t.x(), 4.688319);
  EXPECT_DOUBLE_EQ(gt.T_W_B.t.z(), 0.783338);
  // w comes first in EuRoC's csv.
  const Quat q = Quat(0.534108, -0.153029, -0.827383, -0.082152).normalized();
  EXPECT_LT(gt.T_W_B.q.angularDistance(q), 1e-12);
  EXPECT_NEAR(std::abs(gt.T_W_B.q.w()), q.w(), 1e-12);
  ASSERT_TRUE(gt.v_W && gt.b_g && gt.b_a);
  EXPECT_DOUBLE_EQ(gt.v_W->z(), 0.800006);
  EXPECT_DOUBLE_EQ(gt.b_g->x(), -0.003172);
  EXPECT_DOUBLE_EQ(gt.b_a->z(), 0.075593);
  EXPECT_DOUBLE_EQ(rec.groundtruth.back().T_W_B.t.x(), 4.688319 + 0.0004);
}

TEST(Euroc, AcceptsMav0FolderAndCrlf) {
  ScratchDir dir("euroc-crlf");
  EurocOptions options;
  options.crlf = true;
  const EurocFixture fx = write_euroc_sequence(dir / "V1_02_medium", options);
  const Recording rec = read_euroc(fx.mav0);
  EXPECT_EQ(rec.imu.size(), fx.imu_t.size());
  EXPECT_EQ(rec.frames.size(), 3u);
  EXPECT_EQ(rec.groundtruth.size(), 5u);
}

TEST(Euroc, ReadsStereoAsSecondCamera) {
  ScratchDir dir("euroc-stereo");
  EurocOptions options;
  options.stereo = true;
  const EurocFixture fx = write_euroc_sequence(dir / "MH_01_easy", options);
  const Recording rec = read_euroc(fx.sequence);
  ASSERT_EQ(rec.calibration.cameras.size(), 2u);
  EXPECT_EQ(rec.calibration.cameras[1].name, "cam1");
  EXPECT_DOUBLE_EQ(rec.calibration.cameras[1].fx, 457.587);
  const SE3 T_C1_C0 = rec.calibration.cameras[1].T_B_C.inverse() * rec.calibration.cameras[0].T_B_C;
  EXPECT_NEAR(T_C1_C0.t.x(), -0.110073808127, 1e-9);  // the published stereo baseline
  ASSERT_EQ(rec.frames.size(), 6u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(rec.frames[2 * k].camera, "cam0");
    EXPECT_EQ(rec.frames[2 * k + 1].camera, "cam1");
    EXPECT_EQ(rec.frames[2 * k].t, rec.frames[2 * k + 1].t);
    EXPECT_EQ(rec.frames[2 * k + 1].index, k);
  }
}

TEST(Euroc, GroundTruthIsOptional) {
  ScratchDir dir("euroc-nogt");
  EurocOptions options;
  options.groundtruth = false;
  const EurocFixture fx = write_euroc_sequence(dir / "MH_01_easy", options);
  const Recording rec = read_euroc(fx.sequence);
  EXPECT_TRUE(rec.groundtruth.empty());
  EXPECT_EQ(rec.imu.size(), fx.imu_t.size());
}

TEST(Euroc, PoseOnlyGroundTruth) {
  ScratchDir dir("euroc-gt8");
  const EurocFixture fx = write_euroc_sequence(dir / "MH_01_easy");
  write_text(fx.mav0 / "state_groundtruth_estimate0" / "data.csv",
             "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], q_RS_z []\n"
             "1403636580838555648,4.688319,-1.786938,0.783338,0.534108,-0.153029,-0.827383,-0.082152\n");
  const Recording rec = read_euroc(fx.sequence);
  ASSERT_EQ(rec.groundtruth.size(), 1u);
  EXPECT_FALSE(rec.groundtruth[0].v_W.has_value());
}

TEST(Euroc, NotAnEurocFolder) {
  ScratchDir dir("euroc-none");
  expect_io_error([&] { read_euroc(dir.path()); }, dir.path().string(), 0, {"not an EuRoC/ASL folder"});
  expect_io_error([&] { read_euroc(dir / "absent"); }, "absent", 0, {"is not a folder"});
}

// Corrupt copies: each names the file and line (data) or the file and key (calibration).
class EurocCorrupt : public ::testing::Test {
 protected:
  void SetUp() override { fx_ = write_euroc_sequence(dir_ / "MH_01_easy"); }
  fs::path imu_csv() const { return fx_.mav0 / "imu0" / "data.csv"; }
  fs::path cam_csv() const { return fx_.mav0 / "cam0" / "data.csv"; }
  fs::path gt_csv() const { return fx_.mav0 / "state_groundtruth_estimate0" / "data.csv"; }
  void expect_data_error(const std::string& file_suffix, std::size_t line,
                         std::initializer_list<std::string> fragments) {
    expect_io_error([&] { read_euroc(fx_.sequence); }, file_suffix, line, fragments);
  }
  void expect_calibration_error(const std::string& file_suffix, const std::string& key,
                                std::initializer_list<std::string> fragments = {}) {
    expect_config_error([&] { read_euroc(fx_.sequence); }, file_suffix, key, fragments);
  }
  ScratchDir dir_{"euroc-corrupt"};
  EurocFixture fx_;
};

TEST_F(EurocCorrupt, TruncatedImuLine) {
  replace_line(imu_csv(), 4, "1403636579773555456,-0.096,0.134,0.0289,8.1777,-0.3759");
  expect_data_error("imu0/data.csv", 4, {"expected 7 fields, found 6"});
}

TEST_F(EurocCorrupt, FileCutMidLine) {
  // A copy interrupted mid-line: last line ends after "8.3".
  const std::string text = testing::read_text(imu_csv());
  write_text(imu_csv(), text.substr(0, text.size() - 30));
  const std::size_t last = fx_.imu_t.size() + 1;
  expect_data_error("imu0/data.csv", last, {"fields"});
}

TEST_F(EurocCorrupt, NonNumericField) {
  replace_line(imu_csv(), 3, "1403636579763555584,-0.097,abc,0.0289,8.1577,-0.3759,-2.4026");
  expect_data_error("imu0/data.csv", 3, {"column 'w_RS_S_y'", "'abc' is not a number"});
}

TEST_F(EurocCorrupt, NanAndInf) {
  replace_line(imu_csv(), 3, "1403636579763555584,-0.097,0.138,0.0289,nan,-0.3759,-2.4026");
  expect_data_error("imu0/data.csv", 3, {"column 'a_RS_S_x'", "not a finite number"});
  replace_line(imu_csv(), 3, "1403636579763555584,-0.097,0.138,0.0289,8.1577,-0.3759,-inf");
  expect_data_error("imu0/data.csv", 3, {"column 'a_RS_S_z'", "not a finite number"});
}

TEST_F(EurocCorrupt, TimestampInSecondsInsteadOfNanoseconds) {
  replace_line(imu_csv(), 3, "1403636579.763555584,-0.097,0.138,0.0289,8.1577,-0.3759,-2.4026");
  expect_data_error("imu0/data.csv", 3, {"not an integer time in nanoseconds"});
}

TEST_F(EurocCorrupt, DuplicateImuTimestamp) {
  const std::string line3 = line_of(imu_csv(), 3);
  replace_line(imu_csv(), 4, line3);
  expect_data_error("imu0/data.csv", 4, {"duplicate timestamp"});
}

TEST_F(EurocCorrupt, DecreasingCameraTimestamp) {
  replace_line(cam_csv(), 3, "1403636579713555584,1403636579713555584.png");
  expect_data_error("cam0/data.csv", 3, {"decreasing timestamp 1403636579.713555584"});
}

TEST_F(EurocCorrupt, MissingImageFile) {
  fs::remove(fx_.mav0 / "cam0" / "data" / (std::to_string(fx_.cam_t[1]) + ".png"));
  expect_data_error("cam0/data.csv", 3, {"image file '" + std::to_string(fx_.cam_t[1]) + ".png' does not exist"});
}

TEST_F(EurocCorrupt, EmptyFilename) {
  replace_line(cam_csv(), 2, std::to_string(fx_.cam_t[0]) + ",");
  expect_data_error("cam0/data.csv", 2, {"'filename' is empty"});
}

TEST_F(EurocCorrupt, GroundTruthBadQuaternionAndFieldCount) {
  replace_line(gt_csv(), 3,
               "1403636580843555648,4.688419,-1.786938,0.783338,0.634108,-0.153029,-0.827383,-0.082152,"
               "-0.027876,0.033207,0.800006,-0.003172,0.021267,0.078502,-0.025266,0.136696,0.075593");
  expect_data_error("state_groundtruth_estimate0/data.csv", 3, {"q_RS_w", "not within 1e-3 of 1"});
  replace_line(gt_csv(), 3, "1403636580843555648,4.688419,-1.786938,0.783338,0.534108,-0.153029,-0.827383");
  expect_data_error("state_groundtruth_estimate0/data.csv", 3, {"expected 17 fields", "found 7"});
}

TEST_F(EurocCorrupt, MissingCalibrationKey) {
  replace_text(fx_.mav0 / "cam0" / "sensor.yaml", "intrinsics: [458.654, 457.296, 367.215, 248.375] #fu, fv, cu, cv\n",
               "");
  expect_calibration_error("cam0/sensor.yaml", "intrinsics", {"missing"});
}

TEST_F(EurocCorrupt, MissingNoiseKey) {
  replace_text(fx_.mav0 / "imu0" / "sensor.yaml", "gyroscope_random_walk:", "gyroscope_random_walk_typo:");
  expect_calibration_error("imu0/sensor.yaml", "gyroscope_random_walk", {"missing"});
}

TEST_F(EurocCorrupt, NegativeNoise) {
  replace_text(fx_.mav0 / "imu0" / "sensor.yaml", "accelerometer_noise_density: 2.0000e-3",
               "accelerometer_noise_density: -2.0000e-3");
  expect_calibration_error("imu0/sensor.yaml", "accelerometer_noise_density", {"must be > 0"});
}

TEST_F(EurocCorrupt, MatrixWithFifteenValues) {
  replace_text(fx_.mav0 / "cam0" / "sensor.yaml", "0.0, 0.0, 0.0, 1.0]", "0.0, 0.0, 1.0]");
  expect_calibration_error("cam0/sensor.yaml", "T_BS.data", {"expected 16 values, found 15"});
}

TEST_F(EurocCorrupt, MatrixDeclaredWithWrongShape) {
  replace_text(fx_.mav0 / "cam0" / "sensor.yaml", "rows: 4", "rows: 3");
  expect_calibration_error("cam0/sensor.yaml", "T_BS", {"expected a 4x4 matrix", "rows: 3"});
}

TEST_F(EurocCorrupt, NonRigidExtrinsics) {
  replace_text(fx_.mav0 / "cam0" / "sensor.yaml", "0.999557249008, 0.0149672133247", "0.989557249008, 0.0149672133247");
  expect_calibration_error("cam0/sensor.yaml", "T_BS", {"not orthonormal"});
}

TEST_F(EurocCorrupt, WrongTypeInCalibration) {
  replace_text(fx_.mav0 / "cam0" / "sensor.yaml", "rate_hz: 20", "rate_hz: twenty");
  expect_calibration_error("cam0/sensor.yaml", "rate_hz", {"expected a number, found 'twenty'"});
}

TEST_F(EurocCorrupt, UnknownDistortionModel) {
  replace_text(fx_.mav0 / "cam0" / "sensor.yaml", "distortion_model: radial-tangential", "distortion_model: fov");
  expect_calibration_error("cam0/sensor.yaml", "distortion_model", {"unsupported distortion model 'fov'"});
}

TEST_F(EurocCorrupt, MissingSensorYaml) {
  fs::remove(fx_.mav0 / "cam0" / "sensor.yaml");
  expect_io_error([&] { read_euroc(fx_.sequence); }, "cam0/sensor.yaml", 0, {"does not exist"});
}

TEST_F(EurocCorrupt, GroundTruthOffBodyIsRefused) {
  replace_text(fx_.mav0 / "state_groundtruth_estimate0" / "sensor.yaml", "data: [1.0, 0.0, 0.0, 0.0,",
               "data: [1.0, 0.0, 0.0, 0.1,");
  expect_calibration_error("state_groundtruth_estimate0/sensor.yaml", "T_BS", {"identity T_BS"});
}

}  // namespace
}  // namespace navaid::io
