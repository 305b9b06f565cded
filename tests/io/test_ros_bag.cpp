// ROS 1 bags: bags written by Debian's python3-rosbag in this test (tests/io/fixtures/
// make_ros_bags.py, values known), every real bag of ../shared/data/ros-bags, corrupt bags.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <memory>
#include <random>

#include "navaid/core/errors.hpp"
#include "navaid/io/image_io.hpp"
#include "navaid/io/navaid_recording.hpp"
#include "navaid/io/open_input.hpp"
#include "navaid/io/ros_bag.hpp"
#include "test_support.hpp"

namespace navaid::io {
namespace {

namespace fs = std::filesystem;
using testing::ScratchDir;

constexpr Timestamp kT0 = 1'000'000'000'000;  // the fixtures' first stamp, 1000 s

// The fixture bags, written once per test program.
class RosBagTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    bags_ = std::make_unique<ScratchDir>("ros-bag-fixtures");
    const std::string command = "/usr/bin/python3 '" + std::string(NAVAID_SOURCE_DIR) +
                                "/tests/io/fixtures/make_ros_bags.py' '" + bags_->path().string() + "'";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
  }
  static void TearDownTestSuite() { bags_.reset(); }
  static fs::path bag(const std::string& name) { return bags_->path() / name; }

  static std::unique_ptr<ScratchDir> bags_;
};
std::unique_ptr<ScratchDir> RosBagTest::bags_;

bool has_warning(const Recording& r, const std::string& part) {
  for (const auto& w : r.report.warnings)
    if (w.message.find(part) != std::string::npos) return true;
  return false;
}

TEST_F(RosBagTest, CameraBagGivesEveryStreamWithItsValues) {
  ScratchDir out("ros-bag-camera");
  RosBagReadOptions o;
  o.image_folder = out.path();
  const Recording r = read_ros_bag(bag("camera.bag"), o);  // bz2 chunks, topics found by type
  EXPECT_EQ(r.format, "ros-bag");

  ASSERT_EQ(r.imu.size(), 60u);
  EXPECT_EQ(r.imu[7].t, kT0 + 35'000'000);
  EXPECT_NEAR(r.imu[7].gyro.x(), 0.07, 1e-12);
  EXPECT_NEAR(r.imu[7].accel.z(), 9.817, 1e-12);

  ASSERT_EQ(r.frames.size(), 10u);
  ASSERT_EQ(r.calibration.cameras.size(), 1u);
  const CameraCalibration& c = r.calibration.cameras.front();
  EXPECT_EQ(c.width, 8);
  EXPECT_EQ(c.height, 6);
  EXPECT_EQ(c.fx, 500.0);
  EXPECT_EQ(c.fy, 510.0);
  EXPECT_EQ(c.cx, 4.0);
  EXPECT_EQ(c.cy, 3.0);
  EXPECT_EQ(c.distortion, DistortionModel::kRadialTangential);
  EXPECT_EQ(c.distortion_coeffs, (std::vector<double>{0.1, -0.05, 0.001, 0.002, 0.0}));
  EXPECT_NEAR(c.rate_hz, 30.0, 1e-3);
  // /tf_static: both optical frames hang off camera_link with the same rotation, so T_B_C is a pure
  // translation R^T (t_cam - t_imu) = R^T (0.01, 0.02, -0.006) = (-0.02, 0.006, 0.01).
  EXPECT_TRUE(c.T_B_C.is_approx(SE3(Quat::Identity(), Vec3(-0.02, 0.006, 0.01)), 1e-12));

  for (std::size_t i = 0; i < r.frames.size(); ++i) {
    RgbdFrame f = r.frames[i];
    EXPECT_EQ(f.index, i);
    EXPECT_EQ(f.t, kT0 + static_cast<Timestamp>(std::llround(i / 30.0 * 1e9)));
    EXPECT_TRUE(fs::equivalent(fs::path(f.intensity_path).parent_path(), out / "rgb"));
    load_frame_images(f);
    ASSERT_EQ(f.intensity.channels, 3);
    EXPECT_EQ(f.intensity.at(5, 4, 0), 50);
    EXPECT_EQ(f.intensity.at(5, 4, 1), 80);
    EXPECT_EQ(f.intensity.at(5, 4, 2), 7 + i);
    // 16UC1 millimetres, 1 ms after the colour image: paired.
    EXPECT_FLOAT_EQ(f.depth.at(3, 2), static_cast<float>((1000 + 100 * i + 3) * 0.001));
  }

  // Fix 1 has no covariance (5 m assumed), fix 3 no fix, fix 4 a NaN latitude (skipped).
  ASSERT_EQ(r.gps.size(), 4u);
  EXPECT_EQ(r.gps[0].covariance_enu.diagonal(), Vec3(4, 9, 16));
  EXPECT_EQ(r.gps[1].covariance_enu.diagonal(), Vec3(25, 25, 100));
  EXPECT_EQ(r.gps[0].mode, GpsFixMode::k3D);
  EXPECT_EQ(r.gps[3].mode, GpsFixMode::kNoFix);
  EXPECT_NEAR(r.gps[2].latitude_deg, 47.000002, 1e-12);
  EXPECT_EQ(r.gps[0].altitude_m + r.gps[0].geoid_separation_m, 500.0);  // NavSatFix: above the ellipsoid
  EXPECT_TRUE(has_warning(r, "without a usable position covariance"));
  EXPECT_TRUE(has_warning(r, "without a valid latitude"));

  ASSERT_EQ(r.mag.size(), 15u);
  EXPECT_EQ(r.mag[3].field, Vec3(2e-5, 0, -4e-5));
  ASSERT_EQ(r.groundtruth.size(), 30u);
  EXPECT_NEAR(r.groundtruth[10].T_W_B.t.x(), 1.0, 1e-12);
  EXPECT_NEAR(2 * std::atan2(r.groundtruth[10].T_W_B.q.z(), r.groundtruth[10].T_W_B.q.w()), 0.1, 1e-12);
  EXPECT_FALSE(r.groundtruth[10].v_W.has_value());
}

TEST_F(RosBagTest, WithoutAnImageFolderFramesAreCountedNotExtracted) {
  const Recording r = read_input(bag("camera.bag"));
  EXPECT_EQ(detect_input(bag("camera.bag")), InputKind::kRosBag);
  EXPECT_TRUE(r.frames.empty());
  EXPECT_EQ(r.imu.size(), 60u);
  EXPECT_TRUE(has_warning(r, "10 image messages not extracted"));
  const auto message = testing::error_message<IoError>([&] { read_camera_recording(bag("camera.bag"), "images"); });
  EXPECT_NE(message.find("navaid convert"), std::string::npos) << message;
}

struct EncodingCase {
  const char* image;  // intensity topic or ""
  const char* depth;  // depth topic or ""
  int channels;
  std::vector<int> pixel;  // intensity at (1, 1), per channel (jpeg: within 3)
  std::vector<float> depth_row;  // depth row 1 in metres
};

class RosBagEncodings : public RosBagTest, public ::testing::WithParamInterface<EncodingCase> {};

TEST_P(RosBagEncodings, DecodeToNavaidImages) {
  const EncodingCase& e = GetParam();
  ScratchDir out("ros-bag-encoding");
  RosBagReadOptions o;
  o.image_folder = out.path();
  o.topics.camera_info = "/info";
  o.topics.image = e.image;
  o.topics.depth = *e.depth ? e.depth : "none";  // "none": no depth, the other depth topics are not searched
  const Recording r = read_ros_bag(bag("encodings.bag"), o);  // lz4 chunks
  ASSERT_EQ(r.frames.size(), 3u);
  RgbdFrame f = r.frames[1];
  EXPECT_EQ(f.t, kT0 + 100'000'000);
  load_frame_images(f);
  if (*e.image) {
    ASSERT_EQ(f.intensity.channels, e.channels);
    for (int c = 0; c < e.channels; ++c) EXPECT_NEAR(f.intensity.at(1, 1, c), e.pixel[static_cast<std::size_t>(c)], 3);
  }
  if (*e.depth) {
    ASSERT_EQ(f.depth.width, 4);
    for (int x = 0; x < 4; ++x) EXPECT_FLOAT_EQ(f.depth.at(x, 1), e.depth_row[static_cast<std::size_t>(x)]) << x;
  }
}

INSTANTIATE_TEST_SUITE_P(
    EveryEncoding, RosBagEncodings,
    ::testing::Values(EncodingCase{"/mono", "/depth16be", 1, {1 + 4 + 1}, {1.5f, 1.501f, 1.502f, 1.503f}},
                      EncodingCase{"/bgr", "/depth32", 3, {3, 2, 1}, {1.235f, 0.f, 0.f, 0.f}},
                      EncodingCase{"/rgba", "/cdepth", 3, {9, 8, 7}, {2.5f, 2.501f, 2.502f, 2.503f}},
                      EncodingCase{"/jpeg", "/cdepth32", 3, {200, 100, 50}, {2.f, 2.f, 0.f, 0.f}},
                      EncodingCase{"/png", "", 1, {77}, {}}),
    [](const ::testing::TestParamInfo<EncodingCase>& p) {
      return std::string(p.param.image + 1) + "_" + (*p.param.depth ? p.param.depth + 1 : "none");
    });

TEST_F(RosBagTest, DepthBeyondSixtyFiveMetresIsCountedInvalid) {
  ScratchDir out("ros-bag-depth32");
  RosBagReadOptions o;
  o.image_folder = out.path();
  o.topics.image = "/bgr";
  o.topics.depth = "/depth32";
  o.topics.camera_info = "/info";
  const Recording r = read_ros_bag(bag("encodings.bag"), o);
  EXPECT_TRUE(has_warning(r, "beyond 65.535 m set invalid"));
}

TEST_F(RosBagTest, RealSensePresetMergesSeparateGyroAndAccelerometer) {
  RosBagReadOptions o;
  o.preset = "realsense";
  const Recording r = read_ros_bag(bag("split_imu.bag"), o);
  ASSERT_EQ(r.imu.size(), 41u);  // the gyro's 400 Hz stamps, all inside the accelerometer's span
  for (const auto& s : r.imu) {
    EXPECT_EQ(s.gyro.x(), 0.5);
    EXPECT_NEAR(s.accel.x(), ns_to_seconds(s.t - kT0), 1e-9);  // the 100 Hz ramp, interpolated
    EXPECT_NEAR(s.accel.z(), 9.81, 1e-12);
  }
  // Without the preset, two Imu topics are ambiguous.
  const auto message = testing::error_message<IoError>([&] { read_ros_bag(bag("split_imu.bag")); });
  EXPECT_NE(message.find("/camera/accel/sample, /camera/gyro/sample"), std::string::npos) << message;
}

TEST_F(RosBagTest, OdometryTwistBecomesWorldVelocity) {
  const Recording r = read_ros_bag(bag("odometry.bag"));
  ASSERT_EQ(r.groundtruth.size(), 5u);
  ASSERT_TRUE(r.groundtruth[2].v_W.has_value());
  EXPECT_TRUE(r.groundtruth[2].v_W->isApprox(Vec3(0, 1, 0), 1e-12));  // 1 m/s forward, turned 90 degrees left
  EXPECT_NEAR(r.groundtruth[2].T_W_B.t.y(), 0.2, 1e-12);
}

TEST_F(RosBagTest, AmbiguousMissingOrMistypedTopicsAreClearErrors) {
  auto message = testing::error_message<IoError>([&] { read_ros_bag(bag("two_imus.bag")); });
  EXPECT_NE(message.find("several sensor_msgs/Imu topics (/imu_a, /imu_b)"), std::string::npos) << message;
  EXPECT_NE(message.find("--topic imu=TOPIC"), std::string::npos) << message;
  RosBagReadOptions o;
  o.topics.imu = "/imu_b";
  EXPECT_EQ(read_ros_bag(bag("two_imus.bag"), o).imu.size(), 1u);
  o.topics.imu = "/imu_c";
  message = testing::error_message<IoError>([&] { read_ros_bag(bag("two_imus.bag"), o); });
  EXPECT_NE(message.find("/imu_c (named for imu) is not in the bag; its topics: /imu_a [sensor_msgs/Imu]"),
            std::string::npos)
      << message;
  RosBagReadOptions wrong;
  wrong.topics.gps = "/imu_a";
  message = testing::error_message<IoError>([&] { read_ros_bag(bag("two_imus.bag"), wrong); });
  EXPECT_NE(message.find("is a sensor_msgs/Imu, not a sensor_msgs/NavSatFix"), std::string::npos) << message;
  RosBagReadOptions depth_as_image;
  depth_as_image.topics.image = "/depth32";
  depth_as_image.topics.camera_info = "/info";
  message = testing::error_message<IoError>([&] { read_ros_bag(bag("encodings.bag"), depth_as_image); });
  EXPECT_NE(message.find("does not hold intensity images"), std::string::npos) << message;
  RosBagReadOptions unknown_preset;
  unknown_preset.preset = "kinect";
  EXPECT_TRUE(testing::expect_throw<ConfigError>([&] { read_ros_bag(bag("two_imus.bag"), unknown_preset); }));
}

TEST_F(RosBagTest, TopicsFileAndRoleNames) {
  ScratchDir dir("ros-bag-topics");
  testing::write_text(dir / "ok.yaml", "preset: realsense\nimu: /imu_b\n");
  const auto choice = read_ros_bag_topics_file(dir / "ok.yaml");
  EXPECT_EQ(choice.preset, "realsense");
  EXPECT_EQ(choice.topics.imu, "/imu_b");
  testing::write_text(dir / "bad.yaml", "imu: /a\nlidar: /points\n");
  const auto e = testing::expect_throw<ConfigError>([&] { read_ros_bag_topics_file(dir / "bad.yaml"); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->key(), "lidar");
  testing::write_text(dir / "nested.yaml", "imu: {topic: /a}\n");
  EXPECT_TRUE(testing::expect_throw<ConfigError>([&] { read_ros_bag_topics_file(dir / "nested.yaml"); }));
  RosBagTopics t;
  EXPECT_TRUE(testing::expect_throw<ConfigError>([&] { set_ros_bag_topic(t, "imu", ""); }));
  EXPECT_EQ(ros_bag_roles().size(), 9u);
}

TEST_F(RosBagTest, ConvertWritesANavaidRecordingThatReadsBack) {
  ScratchDir out("ros-bag-convert");
  testing::write_text(out / "imu.yaml",
                      "accelerometer_noise_density: 0.002\naccelerometer_random_walk: 0.0003\n"
                      "gyroscope_noise_density: 0.00017\ngyroscope_random_walk: 0.00002\nupdate_rate: 200.0\n");
  RosBagConversion c;
  c.imu_noise = out / "imu.yaml";
  const fs::path folder = out / "recording";
  convert_ros_bag(bag("camera.bag"), folder, c);
  const Recording back = read_navaid_recording(folder);
  EXPECT_EQ(back.frames.size(), 10u);
  EXPECT_EQ(back.imu.size(), 60u);
  ASSERT_TRUE(back.calibration.imu);
  EXPECT_EQ(back.calibration.imu->gyro_noise_density, 0.00017);
  ASSERT_TRUE(back.origin);  // the first 3D fix
  EXPECT_NEAR(back.origin->latitude_deg, 47.0, 1e-9);
  RgbdFrame f = back.frames[4];
  load_frame_images(f);
  EXPECT_FLOAT_EQ(f.depth.at(2, 1), 1.402f);
  // A second conversion into the same folder needs overwrite, and leaves no stale image.
  EXPECT_TRUE(testing::expect_throw<IoError>([&] { convert_ros_bag(bag("camera.bag"), folder, c); }));
  testing::write_text(folder / "rgb" / "cam0_1.png", "stale");
  c.overwrite = true;
  convert_ros_bag(bag("camera.bag"), folder, c);
  EXPECT_FALSE(fs::exists(folder / "rgb" / "cam0_1.png"));
  // Images without camera_info (the role switched off) and without a camchain cannot be converted.
  RosBagConversion no_camera;
  no_camera.read.topics.image = "/bgr";
  no_camera.read.topics.depth = "/depth16be";
  no_camera.read.topics.camera_info = "none";
  const auto message =
      testing::error_message<IoError>([&] { convert_ros_bag(bag("encodings.bag"), out / "no-info", no_camera); });
  EXPECT_NE(message.find("has images but no camera_info"), std::string::npos) << message;
}

// Truncated bags and flipped bytes: an IoError naming the bag, or a recording; never a crash.
TEST_F(RosBagTest, CorruptBagsFailCleanly) {
  const std::string bytes = testing::read_text(bag("camera.bag"));
  ScratchDir dir("ros-bag-corrupt");
  std::mt19937 rng(7);
  int errors = 0, read = 0;
  for (int k = 0; k < 40; ++k) {
    std::string damaged = bytes;
    if (k < 20) {
      damaged.resize(bytes.size() * static_cast<std::size_t>(k + 1) / 21);
    } else {
      for (int flips = 0; flips < 8; ++flips) damaged[rng() % damaged.size()] = static_cast<char>(rng());
    }
    const fs::path path = dir / ("damaged" + std::to_string(k) + ".bag");
    std::ofstream(path, std::ios::binary) << damaged;
    RosBagReadOptions o;
    o.image_folder = dir / ("out" + std::to_string(k));
    try {
      read_ros_bag(path, o);
      ++read;
    } catch (const IoError& e) {
      ++errors;
      EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    }
  }
  EXPECT_GE(errors, 20);  // every truncation loses the index at the end of the file
  testing::write_text(dir / "text.bag", "not a bag\n");
  const auto message = testing::error_message<IoError>([&] { read_ros_bag(dir / "text.bag"); });
  EXPECT_NE(message.find("is not a ROS 1 bag"), std::string::npos) << message;
  EXPECT_TRUE(testing::expect_throw<IoError>([&] { read_ros_bag(dir / "missing.bag"); }));
}

// Found by fuzz_ros_bag: a header field whose length runs past its record header made
// rosbag_storage's ros::Header::parse read beyond its buffer (a heap-buffer-overflow under ASan).
// The structural check (ros_bag_structure.cpp) now refuses it, and the other lies a bag can tell
// rosbag_storage, before it reads them.
TEST_F(RosBagTest, LengthsThatLieAreRefusedBeforeRosbagStorageReadsThem) {
  const fs::path finding = fs::path(NAVAID_SOURCE_DIR) / "tests/io/fixtures/ros-bag-findings/header-field-overruns-header.bag";
  auto message = testing::error_message<IoError>([&] { list_ros_bag_topics(finding); });
  EXPECT_NE(message.find("a header field of 530 bytes overruns its header"), std::string::npos) << message;
  EXPECT_NE(message.find("at byte 29"), std::string::npos) << message;

  // Uncompressed bags, edited: a field length, a typed field's size, an index entry, a chunk size.
  const std::string bytes = testing::read_text(bag("two_imus.bag"));
  ScratchDir dir("ros-bag-lies");
  const auto with = [&](const std::string& name, const std::function<void(std::string&)>& edit) {
    std::string b = bytes;
    edit(b);
    const fs::path path = dir / name;
    std::ofstream(path, std::ios::binary) << b;
    return testing::error_message<IoError>([&] { read_ros_bag(path); });
  };
  const auto set_u32 = [](std::string& b, std::size_t at, std::uint32_t v) { std::memcpy(&b[at], &v, 4); };
  // The bag header record starts at byte 13: its first field's length is at 17.
  message = with("field.bag", [&](std::string& b) { set_u32(b, 17, 0x7fffffff); });
  EXPECT_NE(message.find("overruns its header"), std::string::npos) << message;
  message = with("header.bag", [&](std::string& b) { set_u32(b, 13, 0xfffffff0); });
  EXPECT_NE(message.find("overruns the file"), std::string::npos) << message;
  message = with("typed.bag", [&](std::string& b) { b.replace(b.find("index_pos="), 10, "index_pox="); });
  EXPECT_NE(message.find("the record has no 'index_pos' field"), std::string::npos) << message;
  message = with("cut.bag", [&](std::string& b) { b.resize(b.size() - 7); });
  EXPECT_NE(message.find("not a well-formed ROS bag"), std::string::npos) << message;
}

// Every real bag of ../shared/data/ros-bags: the counts of BAG_SUMMARY.txt, less what the reader
// says it skipped.
struct RealBag {
  const char* file;
  std::size_t imu, gps, mag, groundtruth;
  const char* groundtruth_topic;
  const char* skipped;  // a warning the real data causes, or ""
};

class RealRosBags : public ::testing::TestWithParam<RealBag> {};

TEST_P(RealRosBags, ReadWithTheSummaryCounts) {
  if (!testing::have_shared_data()) return;
  const RealBag& b = GetParam();
  RosBagReadOptions o;
  o.topics.groundtruth = b.groundtruth_topic;
  const Recording r = read_ros_bag(testing::shared_data_dir() / "ros-bags" / b.file, o);
  EXPECT_EQ(r.imu.size(), b.imu);
  EXPECT_EQ(r.gps.size(), b.gps);
  EXPECT_EQ(r.mag.size(), b.mag);
  EXPECT_EQ(r.groundtruth.size(), b.groundtruth);
  if (*b.skipped) {
    EXPECT_TRUE(has_warning(r, b.skipped)) << b.file;
  }
  for (std::size_t i = 1; i < r.imu.size(); ++i) ASSERT_LT(r.imu[i - 1].t, r.imu[i].t);
  for (const auto& s : r.imu) ASSERT_TRUE(s.accel.allFinite() && s.gyro.allFinite());
}

INSTANTIATE_TEST_SUITE_P(
    SharedData, RealRosBags,
    ::testing::Values(RealBag{"robot_localization_test1.bag", 11865, 989, 0, 3952, "", ""},
                      RealBag{"robot_localization_test2.bag", 3061, 0, 0, 3060, "", ""},
                      // The AR.Drone's raw odometry has no orientation: every pose is skipped, counted.
                      RealBag{"robot_localization_test3.bag", 25217, 0, 0, 0, "", "all-zero quaternion"},
                      RealBag{"imu_tools_ardrone_imu.bag", 4308, 0, 4308, 0, "", ""},
                      // The Phidgets magnetometer publishes NaN half of the time.
                      RealBag{"imu_tools_phidgets_imu_upside_down.bag", 13964, 0, 6974, 0, "", "non-finite magnetic"},
                      RealBag{"imu_tools_sparkfun_razor.bag", 2144, 0, 2144, 0, "", ""},
                      RealBag{"ROS_example.bag", 0, 0, 0, 12765, "groundtruth", ""},
                      RealBag{"tf_example.bag", 0, 0, 0, 0, "", ""}),  // lz4 chunks, /tf only
    [](const ::testing::TestParamInfo<RealBag>& p) {
      std::string name = p.param.file;
      name = name.substr(0, name.find('.'));
      for (auto& ch : name)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
      return name;
    });

TEST(RealRosBagTopics, ListedWithTypesAndCounts) {
  if (!testing::have_shared_data()) return;
  const auto topics = list_ros_bag_topics(testing::shared_data_dir() / "ros-bags" / "ROS_example.bag");
  ASSERT_EQ(topics.size(), 3u);
  EXPECT_EQ(topics[0].topic, "ORB-SLAM");
  EXPECT_EQ(topics[0].type, "geometry_msgs/PoseStamped");
  EXPECT_EQ(topics[0].messages, 8362u);
  EXPECT_EQ(topics[2].messages, 12765u);
  const auto message = testing::error_message<IoError>(
      [&] { read_ros_bag(testing::shared_data_dir() / "ros-bags" / "ROS_example.bag"); });
  EXPECT_NE(message.find("several pose or odometry topics (ORB-SLAM, S-PTAM, groundtruth)"), std::string::npos)
      << message;
}

}  // namespace
}  // namespace navaid::io
